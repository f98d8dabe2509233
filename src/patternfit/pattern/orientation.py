"""Whether a pattern's seams sew it into a surface with one right side, or twist it.

Every panel's triangles face +z in its flat frame (right side up). A seam that joins two
edges running opposite ways along their loops' positive direction (an outline counter-
clockwise, a hole clockwise) keeps the right sides together; one that joins them running the
same way turns one panel over. Going round any cycle of seams, the panels must be turned over
an even number of times; an odd cycle (a Möbius band) cannot be sewn flat on a body and
drapes crumpled and crossed, whatever the solver does. GarmentCode published such a file
(``standing_lapel``: each lapel sewn wrong side out to the front but right side out to its
back collar) next to its correction.
"""

from __future__ import annotations

from .model import Pattern


def twisted_seams(pattern: Pattern) -> list[str]:
    """Names of the seams that close a cycle turning the cloth over an odd number of times
    (empty: the sewn garment has one right side). Only the outlines' directions and the
    seams' ``reverse`` flags count; lengths do not."""
    backwards = {}
    for panel in pattern.panels:
        for k, loop in enumerate(panel.loops):
            wrong_way = (loop.signed_area() < 0) == (k == 0)
            for e in loop.edges:
                backwards[panel.name, e.name] = wrong_way
    links: dict[str, list[tuple[str, bool, str]]] = {}
    for s in pattern.seams:
        turn = not (s.reverse ^ backwards[s.a.panel, s.a.edge] ^ backwards[s.b.panel, s.b.edge])
        links.setdefault(s.a.panel, []).append((s.b.panel, turn, s.name))
        links.setdefault(s.b.panel, []).append((s.a.panel, turn, s.name))
    over: dict[str, bool] = {}
    bad = set()
    for panel in pattern.panels:
        if panel.name in over:
            continue
        over[panel.name] = False
        todo = [panel.name]
        while todo:
            here = todo.pop()
            for there, turn, name in links.get(here, ()):
                if there not in over:
                    over[there] = over[here] ^ turn
                    todo.append(there)
                elif over[there] != over[here] ^ turn:
                    bad.add(name)
    return sorted(bad)
