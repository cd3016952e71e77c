"""The report's document model: Markdown and HTML show the same cells, headings and images."""

from __future__ import annotations

import html
import math
import re

import pytest

from shared import html_tables, md_tables
from socialnav.report.document import (
    Document,
    Heading,
    Image,
    Paragraph,
    Table,
    cell,
    to_html,
    to_markdown,
)


def sample_document() -> Document:
    doc = Document("a <report> & more")
    doc.add(Heading("Results"))
    doc.add(Paragraph("**paccet** beats `traditional` where 1 < 2 & 3 > 2."))
    doc.add(
        Table(
            ["planner", "value", "flag", "note"],
            [
                ["paccet", 1.23456, True, "plain"],
                ["traditional", math.nan, False, "a | b"],
                ["orca", None, 7, "<script>x</script>"],
                ["hl", -0.004, "**bold**", "line one\nline two"],
            ],
            caption="robot `pr2`",
        )
    )
    doc.add(Heading("Figures", level=3))
    doc.add(Image("figures/a b.png", "the 'figure'"))
    doc.add(Table(["only"], [["x"]]))
    return doc


@pytest.mark.parametrize(
    ("value", "text"),
    [
        (1.23456, "1.23"),
        (-0.004, "-0.00"),
        (math.nan, "n/a"),
        (None, "n/a"),
        (True, "✓"),
        (False, "✗"),
        (7, "7"),
        ("x", "x"),
    ],
)
def test_cell_formatting(value, text) -> None:
    assert cell(value) == text


def test_cell_digits() -> None:
    assert cell(math.pi, digits=4) == "3.1416"


def test_markdown_and_html_tables_have_the_same_cells() -> None:
    doc = sample_document()
    md, page = md_tables(to_markdown(doc)), html_tables(to_html(doc))
    assert len(md) == len(page) == 2
    # every table row has as many cells as the header, in both renderings
    assert all(len(r) == 4 for r in md[0]) and all(len(r) == 4 for r in page[0])
    assert md == page
    assert md[0][2] == ["traditional", "n/a", "✗", "a | b"]
    assert md[0][4] == ["hl", "-0.00", "bold", "line one line two"]


def test_markdown_structure() -> None:
    text = to_markdown(sample_document())
    lines = text.splitlines()
    assert lines[0] == "# a <report> & more"
    assert "## Results" in lines and "### Figures" in lines
    assert "*robot `pr2`*" in lines
    assert "|---|---|---|---|" in lines
    assert "![the 'figure'](figures/a b.png)" in lines


def test_html_escapes_and_renders_inline_markup() -> None:
    page = to_html(sample_document())
    assert "<script>" not in page
    assert "&lt;script&gt;x&lt;/script&gt;" in page
    assert "<title>a &lt;report&gt; &amp; more</title>" in page
    assert (
        "<p><b>paccet</b> beats <code>traditional</code> where 1 &lt; 2 &amp; 3 &gt; 2.</p>" in page
    )
    assert "<caption>robot <code>pr2</code></caption>" in page
    assert "<h3>Figures</h3>" in page
    assert "src='figures/a b.png'" in page and "alt='the &#x27;figure&#x27;'" in page


def test_headings_and_images_agree() -> None:
    doc = sample_document()
    md, page = to_markdown(doc), to_html(doc)
    md_heads = re.findall(r"^(#+) (.*)$", md, re.M)
    html_heads = re.findall(r"<h(\d)>(.*?)</h\d>", page)
    assert [(len(h), t) for h, t in md_heads] == [(int(n), html.unescape(t)) for n, t in html_heads]
    assert re.findall(r"!\[[^\]]*\]\(([^)]+)\)", md) == re.findall(r"<img src='([^']+)'", page)
