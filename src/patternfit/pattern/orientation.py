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
    return sorted(twisted_cycles(pattern))


def twisted_cycles(pattern: Pattern) -> dict[str, list[str]]:
    """For each seam closing a twisted cycle (as :func:`twisted_seams`), the seams of that
    cycle in order round it, starting with the closing one. Parity says only that the cycle
    turns the cloth over; re-sewing any one link of it the other way round untwists it, and
    each choice is a different garment (GarmentCode's ``standing_lapel`` has three per side),
    so which seam is wrong is the designer's to say."""
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
    # the seam and panel each panel was reached through, to walk a cycle back round
    came: dict[str, tuple[str, str] | None] = {}
    cycles: dict[str, list[str]] = {}
    for panel in pattern.panels:
        if panel.name in over:
            continue
        over[panel.name], came[panel.name] = False, None
        todo = [panel.name]
        while todo:
            here = todo.pop()
            for there, turn, name in links.get(here, ()):
                if there not in over:
                    over[there], came[there] = over[here] ^ turn, (here, name)
                    todo.append(there)
                elif over[there] != over[here] ^ turn and name not in cycles:
                    cycles[name] = [name] + _path(came, here, there)
    return cycles


def _path(came: dict, a: str, b: str) -> list[str]:
    """The seams from panel ``a`` to panel ``b`` along the search tree ``came``."""
    def up(p):
        chain = []
        while came[p] is not None:
            chain.append((p, came[p][1]))
            p = came[p][0]
        return chain + [(p, None)]
    from_a, from_b = up(a), up(b)
    above_b = [p for p, _ in from_b]
    meet = next(p for p, _ in from_a if p in above_b)
    to_meet = [s for p, s in from_a[:[q for q, _ in from_a].index(meet)]]
    from_meet = [s for p, s in from_b[:above_b.index(meet)]]
    return to_meet + from_meet[::-1]


#: how :func:`twisted_warning` begins, whatever file it names the fix in
TWISTED = "the seams sew the garment twisted"


def twisted_warning(pattern: Pattern, *, fix: str) -> str | None:
    """The reader's warning for a pattern whose seams sew it twisted
    (:func:`twisted_cycles`), ``fix`` saying where in the file the seams' directions are
    written; None when it is not. Read as written: which link is wrong the file does not
    say."""
    twisted = twisted_cycles(pattern)
    if not twisted:
        return None
    return (f"{TWISTED} (a cycle of seams turns the cloth over an odd "
            f"number of times; {fix}), closed by " + ", ".join(sorted(twisted))
            + "; round each cycle (" + "; ".join(", ".join(twisted[k]) for k in sorted(twisted))
            + ") one link is sewn the wrong way round; which one the file does not say "
            "(re-sewing each gives a different garment), so it is read as written")
