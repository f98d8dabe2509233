"""Matplotlib for the pictures patternfit writes: off screen, and text taken literally."""

from __future__ import annotations


def literal_text() -> None:
    """Switch matplotlib's ``text.parse_math`` off for the figures made from here on (see
    :func:`pyplot`); for code that draws on a ``Figure`` without pyplot."""
    import matplotlib

    matplotlib.rcParams["text.parse_math"] = False


def pyplot():
    """``matplotlib.pyplot`` on the Agg backend (files only, no display) with
    ``text.parse_math`` off: names in titles and labels come from users' files, and a
    fabric called ``a $\\frac{1}{$ b`` failed its picture (a mathtext syntax error) while
    ``a $x$ b`` was drawn as maths. Matplotlib is imported here, when a picture is made."""
    import matplotlib

    matplotlib.use("Agg")
    literal_text()
    import matplotlib.pyplot as plt

    return plt
