"""Names (of bodies, joints, frames, loads, symbols) as text of a document: LaTeX text, LaTeX math,
Markdown with HTML. A name is text, never markup: every character that a reader would take for a
command shows as itself (pdflatex's OT1 fonts lack some glyphs: those come from the typewriter font)."""

from __future__ import annotations

import unicodedata

TEXT = {
    "\\": r"\textbackslash{}", "{": r"\{", "}": r"\}", "$": r"\$", "&": r"\&", "#": r"\#", "%": r"\%",
    "<": r"\textless{}", ">": r"\textgreater{}", "|": r"\textbar{}", "'": r"\textquotesingle{}",
    "`": r"\textasciigrave{}", "-": "-{}",  # no -- or --- dashes
    **{c: rf"\texttt{{\char{ord(c)}}}" for c in "_^~\""},
}
MATH = {  # inside \mathrm{...}: commands that pdflatex and MathJax both know (\lt, \gt: see PREAMBLE)
    "\\": r"\backslash ", "{": r"\{", "}": r"\}", "$": r"\$", "&": r"\&", "#": r"\#", "%": r"\%",
    "_": r"\_", "^": r"\wedge ", "~": r"\sim ", "<": r"\lt ", ">": r"\gt ", "|": r"\vert ", " ": r"\ ",
}
MARKDOWN = {
    "&": "&amp;", "<": "&lt;", ">": "&gt;", '"': "&quot;",
    **{c: "\\" + c for c in "\\`*_[]|$~"},
}
GREEK = set(
    "alpha beta gamma delta epsilon zeta eta theta iota kappa lambda mu nu xi pi rho sigma tau upsilon "
    "phi chi psi omega Gamma Delta Theta Lambda Xi Pi Sigma Upsilon Phi Psi Omega".split()
)  # the Greek letters LaTeX has commands for (no \Alpha, \omicron: those are Latin letters' shapes)
PREAMBLE = r"\providecommand{\lt}{<}\providecommand{\gt}{>}"


def latex_text(name: str) -> str:
    """A name in LaTeX text mode: a_b$ → a\\texttt{\\char95}b\\$."""
    return "".join(TEXT.get(c) or _other(c, math=False) for c in name)


def latex_math(name: str) -> str:
    """A name inside \\mathrm{...}: specials as math commands, a space as a math space."""
    return "".join(MATH.get(c) or _other(c, math=True) for c in name)


def markdown_text(name: str) -> str:
    """A name in Markdown (and the HTML it becomes): HTML's specials as entities, Markdown's and
    the math delimiter $ escaped by a backslash, line breaks as spaces."""
    return "".join(MARKDOWN.get(c) or (" " if _control(c) else c) for c in name)


def _control(c: str) -> bool:
    return unicodedata.category(c) in ("Cc", "Cf", "Cs", "Co", "Cn", "Zl", "Zp")


def _other(c: str, math: bool) -> str:
    """A letter, digit or harmless sign as itself; a control character as a space or ?; a Greek
    letter as its command; another non-ASCII character as its ASCII decomposition (escaped), or ?."""
    if " " < c < "\x7f":
        return c
    if _control(c) or c.isspace():
        return (r"\ " if math else " ") if c.isspace() else "?"
    name = unicodedata.name(c, "")
    letter = name.split(" LETTER ")[-1].lower().replace("lamda", "lambda").replace("final ", "")
    letter = letter.capitalize() if "CAPITAL" in name else letter
    if name.startswith("GREEK") and " LETTER " in name and letter in GREEK:
        return f"\\{letter} " if math else f"$\\{letter}$"
    plain = "".join(x for x in unicodedata.normalize("NFKD", c) if " " <= x < "\x7f")
    return (latex_math if math else latex_text)(plain) if plain else "?"
