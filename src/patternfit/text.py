"""Names and messages from files, as they may be shown to a person.

A name read from a file (a panel, an edge, a fabric) can hold control characters: an escape
sequence reaching a terminal recolours or rewrites it, a bell rings, a line break breaks a
table, and ``\\x1f`` is the separator of a mesh's stored edge names. Readers refuse them in
names (:func:`control_at`); whatever is printed anyway (a message quoting a refused value or
a file's name) is shown through :func:`printable`.
"""

from __future__ import annotations

import re

#: the C0 and C1 control characters and DEL
CONTROL = re.compile(r"[\x00-\x1f\x7f-\x9f]")
#: the same but the line break, which a multi-line message keeps
_CONTROL_IN_TEXT = re.compile(r"[\x00-\x09\x0b-\x1f\x7f-\x9f]")


def control_at(text: str) -> int | None:
    """Index of the first control character in ``text``, or None when it has none."""
    found = CONTROL.search(text)
    return None if found is None else found.start()


def printable(text: str) -> str:
    """``text`` with every control character but the line break written as Python writes
    it in a string (``\\x1b``), so that it shows instead of acting on the terminal."""
    return _CONTROL_IN_TEXT.sub(lambda m: repr(m.group())[1:-1], text)
