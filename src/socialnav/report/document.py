"""A tiny document model rendered to both Markdown and HTML, so the two never disagree."""

from __future__ import annotations

import base64
import html
import math
import mimetypes
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any


@dataclass
class Heading:
    text: str
    level: int = 2


@dataclass
class Paragraph:
    text: str


@dataclass
class Table:
    header: list[str]
    rows: list[list[Any]]
    caption: str = ""


@dataclass
class Image:
    path: str
    alt: str
    width: int = 900


@dataclass
class Document:
    title: str
    blocks: list[Heading | Paragraph | Table | Image] = field(default_factory=list)

    def add(self, block: Heading | Paragraph | Table | Image) -> None:
        self.blocks.append(block)


def cell(value: Any, digits: int = 2) -> str:
    """Human formatting: floats to ``digits``, NaN as n/a, booleans as ✓/✗."""
    if value is None:
        return "n/a"
    if isinstance(value, bool):
        return "✓" if value else "✗"
    if isinstance(value, float):
        if math.isnan(value):
            return "n/a"
        return f"{value:.{digits}f}"
    return str(value)


def _md_cell(text: str) -> str:
    """A table cell on one line with its pipes escaped (an error message may hold either)."""
    return " ".join(text.split("\n")).replace("|", "\\|")


def to_markdown(doc: Document) -> str:
    out = [f"# {doc.title}", ""]
    for b in doc.blocks:
        if isinstance(b, Heading):
            out += ["#" * b.level + " " + b.text, ""]
        elif isinstance(b, Paragraph):
            out += [b.text, ""]
        elif isinstance(b, Table):
            if b.caption:
                out += [f"*{b.caption}*", ""]
            out.append("| " + " | ".join(_md_cell(h) for h in b.header) + " |")
            out.append("|" + "|".join("---" for _ in b.header) + "|")
            out += ["| " + " | ".join(_md_cell(cell(v)) for v in row) + " |" for row in b.rows]
            out.append("")
        else:
            out += [f"![{b.alt}]({b.path})", ""]
    return "\n".join(out)


def _inline(text: str) -> str:
    """Escape, then render the two inline Markdown forms the report uses: **bold** and `code`."""
    escaped = html.escape(text)
    parts = escaped.split("**")
    escaped = "".join(f"<b>{p}</b>" if i % 2 else p for i, p in enumerate(parts))
    parts = escaped.split("`")
    return "".join(f"<code>{p}</code>" if i % 2 else p for i, p in enumerate(parts))


def data_uri(path: Path) -> str:
    """The file as a ``data:`` URI (base64), so the page that shows it needs no other file."""
    kind = mimetypes.guess_type(path.name)[0] or "application/octet-stream"
    return f"data:{kind};base64," + base64.b64encode(path.read_bytes()).decode("ascii")


def to_html(doc: Document, embed_from: Path | None = None) -> str:
    """The document as one HTML page; with ``embed_from``, images (paths relative to that folder)
    are embedded as data URIs, so the page is a single file that can be mailed as it is. An image
    file that is missing stays a relative link."""
    style = (
        "body{font-family:system-ui,sans-serif;max-width:1100px;margin:2em auto;padding:0 1em}"
        "table{border-collapse:collapse;margin:1em 0;font-size:14px}"
        "td,th{border:1px solid #ccc;padding:3px 8px;text-align:right}"
        "th{background:#f3f3f3}td:first-child,th:first-child{text-align:left}"
        "caption{caption-side:top;font-style:italic;text-align:left}img{max-width:100%}"
    )
    out = [
        "<!DOCTYPE html>",
        f"<html><head><meta charset='utf-8'><title>{html.escape(doc.title)}</title>",
        f"<style>{style}</style></head><body>",
        f"<h1>{html.escape(doc.title)}</h1>",
    ]
    for b in doc.blocks:
        if isinstance(b, Heading):
            out.append(f"<h{b.level}>{_inline(b.text)}</h{b.level}>")
        elif isinstance(b, Paragraph):
            out.append(f"<p>{_inline(b.text)}</p>")
        elif isinstance(b, Table):
            out.append("<table>")
            if b.caption:
                out.append(f"<caption>{_inline(b.caption)}</caption>")
            out.append("<tr>" + "".join(f"<th>{_inline(h)}</th>" for h in b.header) + "</tr>")
            for row in b.rows:
                out.append("<tr>" + "".join(f"<td>{_inline(cell(v))}</td>" for v in row) + "</tr>")
            out.append("</table>")
        else:
            source = b.path
            if embed_from is not None and (embed_from / b.path).is_file():
                source = data_uri(embed_from / b.path)
            out.append(
                f"<p><img src='{html.escape(source)}' alt='{html.escape(b.alt)}' "
                f"width='{b.width}'></p>"
            )
    out.append("</body></html>")
    return "\n".join(out)
