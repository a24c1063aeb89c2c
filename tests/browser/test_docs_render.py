"""The built documentation opened in headless Chromium (Debian's chromium, driven by Playwright) with every
request that leaves the build refused: each page with math has it typeset by MathJax 3 (mjx-container
elements; no merror, no undefined macro drawn in red), every notebook page has math, and no page shows
raw LaTeX (\\( \\[ $$...$$ \\begin), a Markdown table (| --- |) or a progress bar (0%|) in its text.

Run after the docs are built: `pytest -m browser tests/browser` (.ci/run does); the build is read from
docs/_build/html or $EOMGEN_DOCS_HTML, Chromium from /usr/bin/chromium or $EOMGEN_CHROMIUM, and with
$EOMGEN_DOCS_SHOTS set each page's full screenshot is written there as a PNG."""
import os
import re
from pathlib import Path

import pytest

pytestmark = pytest.mark.browser

ROOT = Path(__file__).parents[2]
HTML = Path(os.environ.get("EOMGEN_DOCS_HTML", ROOT / "docs" / "_build" / "html")).resolve()
CHROMIUM = os.environ.get("EOMGEN_CHROMIUM", "/usr/bin/chromium")
ARGS = ["--headless", "--no-sandbox", "--disable-gpu", "--disable-background-networking",
        "--disable-component-update", "--no-first-run", "--disable-sync"]
SOURCES = sorted(
    p.relative_to(ROOT / "docs").with_suffix("")
    for p in (ROOT / "docs").rglob("*")
    if p.suffix in (".md", ".ipynb") and not {"_build", ".ipynb_checkpoints"} & set(p.parts)
)
RAW = re.compile(  # \( or \[; $$...$$ or $...\macro...$; \begin{; a Markdown table's rule; a tqdm bar
    r"\\\(|\\\[|\$\$[^$]+\$\$|\$[^$\n]*\\[A-Za-z]+[^$\n]*\$|\\begin\{|\|\s*:?-{3,}:?\s*\||\d%\|")

TYPESET = """() => {  // each typeset formula's LaTeX, and those MathJax drew as an error
    const math = Array.from(MathJax.startup.document.math), errors = [];
    for (const item of math) {
        item.root.walkTree(node => {
            const red = node.isKind("mtext") && node.attributes.get("mathcolor") === "red";
            if (node.isKind("merror") || red)
                errors.push(item.math.slice(0, 300));
        });
    }
    return {formulas: math.length, errors: errors,
            containers: document.querySelectorAll("mjx-container").length,
            merrors: document.querySelectorAll("mjx-merror").length};
}"""
TEXT = """() => {  // the text as read, less code (cells, blocks, inline: literal by intent) and the math
    const main = document.querySelector("article") || document.body, copy = main.cloneNode(true);
    copy.querySelectorAll(".cell_input, div.highlight:not(.output *), code:not(.output *), mjx-container, "
                          + "script, style")
        .forEach(e => e.remove());
    document.body.appendChild(copy);  // innerText needs a rendered element
    const text = copy.innerText;
    copy.remove();
    return text;
}"""


@pytest.fixture(scope="module")
def browser():
    from playwright.sync_api import sync_playwright

    assert (HTML / "index.html").is_file(), f"no built docs at {HTML}: run sphinx-build -b html docs first"
    with sync_playwright() as p:
        chromium = p.chromium.launch(executable_path=CHROMIUM, args=ARGS, headless=True)
        yield chromium
        chromium.close()


@pytest.mark.parametrize("source", SOURCES, ids=str)
def test_page_renders_offline(browser, source):
    path = HTML / source.with_suffix(".html")
    assert path.is_file(), f"{source} was not built"
    page, outside = browser.new_page(viewport={"width": 1200, "height": 900}), []

    def only_the_build(route):  # the page works offline or this test fails
        url = route.request.url
        if url.startswith(HTML.as_uri()):
            route.continue_()
        else:
            outside.append(url)
            route.abort()

    page.route("**/*", only_the_build)
    page.goto(path.as_uri(), wait_until="load")
    assert not outside, f"{source}: requests off the build: {outside[:5]}"
    has_math = 'class="math' in path.read_text(encoding="utf-8")
    assert has_math or source.parts[0] != "notebooks", f"{source}: a notebook page without math"
    if has_math:
        page.wait_for_function("() => window.MathJax && MathJax.startup && MathJax.startup.promise")
        page.evaluate("() => MathJax.startup.promise")
        typeset = page.evaluate(TYPESET)
        assert typeset["formulas"] > 0 and typeset["containers"] == typeset["formulas"], (source, typeset)
        assert not typeset["errors"] and typeset["merrors"] == 0, (source, typeset["errors"][:5])
    text = page.evaluate(TEXT)
    raw = sorted({text[max(m.start() - 40, 0):m.end() + 40] for m in RAW.finditer(text)})
    assert not raw, f"{source}: raw text on the page: {raw[:5]}"
    if os.environ.get("EOMGEN_DOCS_SHOTS"):
        shots = Path(os.environ["EOMGEN_DOCS_SHOTS"])
        shots.mkdir(parents=True, exist_ok=True)
        page.screenshot(path=shots / f"{'_'.join(source.parts)}.png", full_page=True)
    page.close()
