"""What the studio says to a designer: edits in words for the history ("moved front/waist
2.0 cm right"), and refusals without the programmer's wording (exception class names,
argument names, Python reprs)."""

from __future__ import annotations

import math
import re


def _cm(metres: float) -> str:
    return f"{abs(metres) * 100:.1f} cm"


def _offset(offset) -> str:
    """``[dx, dy]`` [m] in words: "2.0 cm right and 0.5 cm up" ("by 0.0 cm" when nothing)."""
    try:
        dx, dy = (float(c) for c in offset)
    except (TypeError, ValueError):
        return "by an offset"
    parts = [f"{_cm(v)} {word[v > 0]}" for v, word in ((dx, ("left", "right")),
                                                         (dy, ("down", "up")))
             if math.isfinite(v) and abs(v) >= 5e-5]
    return " and ".join(parts) or "by 0.0 cm"


def _percent(factor) -> str:
    try:
        return f"{float(factor) * 100:.1f} %"
    except (TypeError, ValueError):
        return str(factor)


def describe_edit(op: str, args: dict) -> str:
    """The history label of editing tool ``op`` with ``args`` (lengths [m]), in words."""
    a = args
    panel = a.get("panel")
    follows = " (seam partner follows)" if a.get("partner") else ""
    if op == "move_point":
        return f"moved {panel}/{a.get('corner')} {_offset(a.get('offset'))}{follows}"
    if op == "move_edge":
        return f"moved edge {panel}/{a.get('edge')} {_offset(a.get('offset'))}{follows}"
    if op == "edit_curve":
        return (f"reshaped {panel}/{a.get('edge')} (control point {a.get('control', 1)}) "
                f"{_offset(a.get('offset'))}{follows}")
    if op == "lengthen":
        amount = a.get("amount")
        verb = "shortened" if isinstance(amount, (int, float)) and amount < 0 else "lengthened"
        return f"{verb} {panel} by {_length(amount)} from {a.get('a')} to {a.get('b')}{follows}"
    if op == "grade":
        which = panel or "every panel"
        return (f"graded {which} to {_percent(a.get('sx'))} wide, {_percent(a.get('sy'))} "
                f"long{follows}")
    if op == "insert_dart":
        return (f"added dart {panel}/{a.get('name')} ({_length(a.get('length'))} long, "
                f"{_length(a.get('width'))} wide)")
    if op == "move_dart":
        return f"moved dart {panel}/{a.get('name')} {_offset(a.get('offset'))}"
    if op == "resize_dart":
        sizes = [f"{_length(a[k])} {w}" for k, w in (("length", "long"), ("width", "wide"))
                 if a.get(k) is not None]
        return f"resized dart {panel}/{a.get('name')} to {', '.join(sizes) or 'its size'}"
    if op == "add_seam":
        return f"sewed {_side(a.get('a'))} to {_side(a.get('b'))}" + \
            (f" with {_percent(a['ease'])} ease" if a.get("ease") else "")
    if op == "remove_seam":
        return f"unpicked seam {a.get('name')}"
    if op == "set_seam_ease":
        ease = a.get("ease")
        return f"set the ease of seam {a.get('name')} to " + \
            ("none" if not ease else _percent(ease))
    return op.replace("_", " ")


def _length(metres) -> str:
    return _cm(float(metres)) if isinstance(metres, (int, float)) else "an unknown length"


def _side(side) -> str:
    if isinstance(side, dict):
        return f"{side.get('panel')}/{side.get('edge')}"
    if isinstance(side, (list, tuple)) and len(side) >= 2:
        return f"{side[0]}/{side[1]}"
    return str(side)


#: programmer's wording -> a designer's
_PHRASES = [
    (re.compile(r"^(?:[A-Z]\w*(?:Error|Exception)): "), ""),
    (re.compile(r"\bop: unknown edit '(\w+)'.*"), r"there is no editing tool '\1'"),
    (re.compile(r"\bgot an unexpected keyword argument '(\w+)'"), r"does not take '\1'"),
    (re.compile(r"\bmissing (\d+) required (?:positional|keyword-only) arguments?: "),
     r"needs "),
    (re.compile(r"\bargs: "), ""),
    # the command line's fix for an unsewn pattern is the seam tool in the studio
    (re.compile(r"patternfit seams \S+ --suggest --accept \(or (?:add seams with )?--set\)"),
     "open the seam tool (key s) and sew the pieces, or take its suggestions"),
    # a grade's factors are shown as percentages in the page
    (re.compile(r"\bs([xy]): expected a number in \[([\d.e+-]+), ([\d.e+-]+)\], got ([\d.e+-]+)"),
     lambda m: f"the {'width' if m[1] == 'x' else 'length'} must stay between "
               f"{float(m[2]) * 100:g} % and {float(m[3]) * 100:g} %, not {float(m[4]) * 100:g} %"),
    # (not a request's "args.offset: ", which names the field for the script that sent it)
    (re.compile(r"(?<![.\w])offset: "), "the move: "),
]


def designer_message(exc: BaseException) -> str:
    """The message of a refused request as the page shows it: the reason in words, with no
    exception class or Python wording."""
    if isinstance(exc, KeyError) and exc.args:  # str() of a KeyError is the key's repr
        text = f"not found: {exc.args[0]}"
    else:
        text = str(exc) or "refused"
    for pattern, words in _PHRASES:
        text = pattern.sub(words, text)
    return text
