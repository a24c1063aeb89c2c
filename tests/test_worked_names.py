"""Names in worked solutions are text, never markup: a body, joint, link, load or symbol name shows in
the PDF as itself (pdftotext of the compiled document reads it back), cannot make pdflatex read a file,
and arrives in Markdown and the Jupyter display as text, not as HTML (markdown-it renders it, Python's
HTML parser reads the result). pdflatex itself runs with paranoid file access: even LaTeX that is not
escaped cannot read a file outside its folder."""

from __future__ import annotations

import html
import re
import shutil
import string
import subprocess
from html.parser import HTMLParser
from pathlib import Path
from xml.sax.saxutils import quoteattr

import pytest
import sympy as sp
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from markdown_it import MarkdownIt

import eomgen as eg
from eomgen.__main__ import main
from eomgen.escaping import PREAMBLE, latex_math, latex_text, markdown_text
from eomgen.worked.compile import compile_pdf

SECRET = "SECRET-7f3a9c"
IMG = "<img src=x onerror=alert(1)>"
URDF = """<?xml version="1.0"?>
<robot name="r">
 <link name="base"/>
 <link name={link}><inertial><origin xyz="0 0 0.1"/><mass value="1"/>
  <inertia ixx="0.1" ixy="0" ixz="0" iyy="0.1" iyz="0" izz="0.1"/></inertial></link>
 <joint name={joint} type="revolute"><parent link="base"/><child link={link}/><axis xyz="1 0 0"/>
  <limit lower="-1" upper="1" effort="1" velocity="1"/></joint>
</robot>
"""
PRINTABLE = string.ascii_letters + string.digits + string.punctuation + " "


def pdf_text(pdf: Path) -> str:
    """The PDF's text (poppler's pdftotext, also beyond the page's right edge), each run of white space
    as one space."""
    return " ".join(pdf_lines(pdf).split())


def pdf_lines(pdf: Path) -> str:
    exe = shutil.which("pdftotext")
    assert exe, "pdftotext is needed (poppler-utils)"
    area = ["-x", "0", "-y", "0", "-W", "100000", "-H", "100000"]
    return subprocess.run([exe, *area, "-raw", str(pdf), "-"], capture_output=True, text=True,
                          check=True).stdout


def shown(name: str) -> str:
    """A name as text shows it: white space runs as one space, none at the ends."""
    return " ".join(name.split())


class Html(HTMLParser):
    """The tags and the text of an HTML document."""

    def __init__(self, html: str) -> None:
        super().__init__(convert_charrefs=True)
        self.tags, self.chunks = [], []
        self.feed(html)

    def handle_starttag(self, tag, attrs):
        self.tags.append((tag, attrs))

    def handle_data(self, data):
        self.chunks.append(data)


def to_html(markdown: str) -> str:
    """Markdown rendered as CommonMark with GFM tables, raw HTML allowed (as Jupyter's renderer does)."""
    return MarkdownIt("commonmark", {"html": True}).enable("table").render(markdown)


def assert_text_only(markdown: str, names: list[str]) -> None:
    html = Html(to_html(markdown))
    allowed = {"h1", "h2", "h3", "p", "table", "thead", "tbody", "tr", "th", "td", "strong", "em", "code"}
    assert all(tag in allowed and not attrs for tag, attrs in html.tags), html.tags
    text = " ".join(" ".join(html.chunks).split())
    for name in names:
        assert shown(name) in text, (name, text)


def urdf_system(tmp_path: Path, link: str, joint: str) -> eg.System:
    path = tmp_path / "r.urdf"
    path.write_text(URDF.format(link=quoteattr(link), joint=quoteattr(joint)), encoding="utf-8")
    return eg.from_urdf(path)


def test_a_link_named_input_shows_its_name_and_reads_no_file(tmp_path):
    """A URDF link named $\\input{FILE}$ (and a joint \\input{FILE}): the PDF shows the names, not the
    file; the same through `eomgen solve`."""
    secret = tmp_path / "secret.tex"
    secret.write_text(SECRET + "\n")
    link, joint = rf"$\input{{{secret}}}$", rf"\input{{{secret}}}"
    system = urdf_system(tmp_path, link, joint)
    sol = eg.solution(system, methods=("recursive",))
    text = pdf_text(sol.pdf(tmp_path / "s.pdf"))
    assert SECRET not in text and link in text and f"{joint}: Revolute" in text
    model = tmp_path / "model.py"
    model.write_text(f"import eomgen as eg\nsystem = eg.from_urdf({str(tmp_path / 'r.urdf')!r})\n")
    assert main(["solve", str(model), "--methods", "recursive", "-o", str(tmp_path / "cli.pdf")]) == 0
    text = pdf_text(tmp_path / "cli.pdf")
    assert SECRET not in text and link in text


def test_pdflatex_cannot_read_a_file_outside_its_folder(tmp_path):
    """LaTeX that reaches pdflatex unescaped (a step's math is LaTeX by design) still cannot read a
    file by its absolute path or write one: pdflatex runs with openin_any=p, openout_any=p."""
    secret = tmp_path / "secret.tex"
    secret.write_text(SECRET + "\n")
    system = eg.System()
    system.add_body("rod", joint=eg.Revolute("theta", axis=(0, 0, 1)), mass=1)
    read = eg.Step("Reading", rf"$\input{{{secret}}}$", {})
    sol = eg.Solution("t", system, [read], ("recursive",), "textbook")
    with pytest.raises(eg.ModelError, match="pdflatex failed"):
        sol.pdf(tmp_path / "read.pdf")
    assert not (tmp_path / "read.pdf").exists()
    target = tmp_path / "written.tex"
    write = rf"\newwrite\w\immediate\openout\w={target}\immediate\write\w{{x}}\immediate\closeout\w"
    document = rf"\documentclass{{article}}\begin{{document}}{write}x\end{{document}}"
    with pytest.raises(eg.ModelError, match="pdflatex failed"):
        compile_pdf(document, tmp_path / "w.pdf")
    assert not target.exists()


def test_symbol_and_load_names_with_specials_compile(tmp_path):
    """Symbols named a$b, x^2}, \\input{...} and a load named 50% & <more> compile; the names show."""
    secret = tmp_path / "secret.tex"
    secret.write_text(SECRET + "\n")
    m, l, k = sp.Symbol("a$b", positive=True), sp.Symbol("x^2}"), sp.Symbol(rf"\input{{{secret}}}")
    system = eg.System(gravity=(0, -sp.Symbol("g"), 0))
    rod = system.add_body("rod", joint=eg.Revolute("φ_1", axis=(0, 0, 1)), mass=m, com=(l, 0, 0))
    system.add_torque(rod, (0, 0, k), name="50% & <more>")
    sol = eg.solution(system)
    text = pdf_text(sol.pdf(tmp_path / "s.pdf"))
    assert SECRET not in text and "50% & <more>" in text
    assert_text_only(sol.markdown(), ["50% & <more>"])


def test_markdown_and_jupyter_show_an_html_name_as_text():
    """A body, joint and load named like an HTML tag: the rendered Markdown of the solution and of the
    equations' Jupyter display has no tag, and shows the names."""
    system = eg.System(gravity=(0, -9.81, 0))
    body = system.add_body(IMG, joint=eg.Revolute("<b>j|*x*|</b>", axis=(0, 0, 1)), mass=1, com=(1, 0, 0))
    system.add_torque(body, (0, 0, sp.Symbol("T")), name="[click](javascript:alert(1)) `$x$`")
    sol = eg.solution(system, methods=("recursive",))
    names = [IMG, "<b>j|*x*|</b>", "[click](javascript:alert(1)) `$x$`"]
    assert_text_only(sol.markdown(), names)
    assert_text_only(sol._repr_markdown_(), names)
    assert_text_only(eg.derive(system)._repr_markdown_(), names[2:])
    assert "<" not in eg.derive(system)._repr_latex_()


def test_kane_display_and_solution_show_an_html_name_as_text(tmp_path):
    """Kane's equations of a particle on the line x = a y whose dependent coordinate is named like an
    HTML tag: the Jupyter display and the solution's Markdown have no tag; the PDF shows the body."""
    m, a, g = sp.symbols("m a g", positive=True)
    system = eg.System(gravity=(0, -g, 0))
    rail = system.add_body("rail", joint=eg.Prismatic(IMG, axis=(1, 0, 0)))
    system.add_body(IMG + "p", parent=rail, joint=eg.Prismatic("y", axis=(0, 1, 0)), mass=m,
                    inertia=sp.zeros(3))
    x, y = system.q
    k = eg.kane(system, holonomic=[x - a * y], dependent_coordinates=[x], independent=[system.u[1]])
    assert_text_only(k._repr_markdown_(), [])
    sol = eg.solution(k)
    assert_text_only(sol.markdown(), [IMG + "p"])
    assert IMG + "p" in pdf_text(sol.pdf(tmp_path / "k.pdf"))


names = st.text(alphabet=st.sampled_from(PRINTABLE), min_size=1, max_size=10).filter(str.strip)


@settings(max_examples=10, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(body=names, joint=names, load=names, parameter=names)
def test_random_names_through_latex_pdf_and_markdown(tmp_path, body, joint, load, parameter):
    """Random names of printable characters (LaTeX's, Markdown's and HTML's specials among them) as a
    body, a joint (and its coordinate), a load and a symbol: the document compiles, pdftotext shows
    each name, and the Markdown renders them as text."""
    system = eg.System(gravity=(0, -sp.Symbol("g"), 0))
    rod = system.add_body("b" + body, joint=eg.Revolute("j" + joint, axis=(0, 0, 1)), mass=1,
                          com=(sp.Symbol("p" + parameter), 0, 0))
    system.add_torque(rod, (0, 0, sp.Symbol("T")), name="L" + load)
    sol = eg.solution(system, methods=("free_cut",))
    assert sol.latex().count(r"\begin{document}") == 1
    text = pdf_text(sol.pdf(tmp_path / "s.pdf"))
    for name in ("b" + body, "j" + joint, "L" + load):
        assert shown(name) in text, (name, text)
    assert_text_only(sol.markdown(), ["b" + body, "j" + joint, "L" + load])


@settings(max_examples=5, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(printable=st.lists(names, min_size=40, max_size=40), anything=st.lists(st.text(), max_size=40))
def test_escaped_names_read_back_from_the_pdf(tmp_path, printable, anything):
    """Many names in one document, one per line: printable ones read back from the PDF as themselves
    (text mode); any text at all (control characters, any Unicode) compiles as text and as math."""
    lines = [rf"\noindent\mbox{{{latex_text(n)}}}\par" for n in printable]
    lines += [rf"\noindent\mbox{{{latex_text(n)} $\mathrm{{{latex_math(n)}}}$}}\par" for n in anything]
    document = "\n".join([r"\documentclass{article}\usepackage{amsmath,amssymb}", PREAMBLE,
                          r"\pagestyle{empty}\begin{document}", *lines, r"\end{document}"])
    out = pdf_lines(compile_pdf(document, tmp_path / "n.pdf"))
    got = [shown(line) for line in out.splitlines() if line.strip()]
    assert got[: len(printable)] == [shown(n) for n in printable]


@settings(max_examples=200, deadline=None)
@given(name=st.text(min_size=1))
def test_any_name_in_markdown_renders_as_its_text(name):
    """Any text (control characters and any Unicode included) in a Markdown table cell renders as that
    text, line breaks as spaces, and makes no tag."""
    page = to_html(f"| a |\n|---|\n| x{markdown_text(name)}x |\n")
    assert [tag for tag, _ in Html(page).tags] == ["table", "thead", "tr", "th", "tbody", "tr", "td"]
    cell = html.unescape(re.search("<td>(.*)</td>", page, re.S).group(1))
    expected = "".join(" " if c.isspace() or not c.isprintable() else c for c in name)
    assert " ".join(cell.split()) == " ".join(f"x{expected}x".split())
