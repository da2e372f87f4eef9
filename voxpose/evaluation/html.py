"""Tables as standalone HTML pages, shown inline by Snakemake's report (``snakemake --report``).

Snakemake's report shows an HTML result inside the page, where a CSV is only a download. Every page is
self-contained (inline style, images as data URIs), legible at the report's width: 15 px text, numbers right
aligned with a value's 95 % interval on the line below it (a table of intervals then fits beside the
report's info panel), measured rows shaded apart from the paper's.
"""

import base64
import html
from pathlib import Path

import pandas as pd

from voxpose.io.atomic import atomic_path

_STYLE = """
body { font: 15px/1.45 -apple-system, "Segoe UI", Helvetica, Arial, sans-serif; color: #222; margin: 8px; }
h1 { font-size: 21px; margin: 4px 0 8px; } h2 { font-size: 18px; margin: 18px 0 6px; }
table { border-collapse: collapse; margin: 6px 0 4px; }
th, td { border: 1px solid #bbb; padding: 3px 5px; } th { background: #eee; text-align: center; }
td.num { text-align: right; font-variant-numeric: tabular-nums; white-space: nowrap; }
td.num small { display: block; color: #555; }
tr.ours td { background: #eaf2fb; } tr.paper td { background: #fff; } tr.diff td { color: #555; font-style: italic; }
td.held { color: #15661f; font-weight: bold; } td.reversed { color: #a11; font-weight: bold; }
td.notshown { color: #8a5a00; font-weight: bold; }
p.caption { max-width: 1100px; color: #333; } img { max-width: 100%; }
"""


def cell(value, digits: int = 1) -> str:
    """A number with ``digits`` decimals ('' for NaN), or the escaped text."""
    if isinstance(value, float):
        return "" if value != value else f"{value:.{digits}f}"
    return html.escape(str(value))


def with_interval(value, low, high, digits: int = 1) -> str:
    """``4.1 [3.8, 4.5]``: a value and its 95 % interval ('' for NaN)."""
    if value != value:
        return ""
    return f"{value:.{digits}f} <small>[{low:.{digits}f}, {high:.{digits}f}]</small>"


def table(df: pd.DataFrame, row_classes=None, raw_columns=(), cell_classes=None) -> str:
    """A DataFrame as an HTML table; ``raw_columns`` hold ready HTML (intervals), ``row_classes`` one CSS class
    per row (``ours``, ``paper``, ``diff``), ``cell_classes`` {column: per-row classes}."""
    head = "".join(f"<th>{html.escape(str(c))}</th>" for c in df.columns)
    rows = []
    for i, row in enumerate(df.itertuples(index=False)):
        cells = []
        for col, v in zip(df.columns, row, strict=True):
            classes = ["num"] if isinstance(v, int | float) or col in raw_columns else []
            classes += [c for c in [(cell_classes or {}).get(col, [""] * len(df))[i]] if c]
            body = str(v) if col in raw_columns else cell(v)
            cells.append(f'<td class="{" ".join(classes)}">{body}</td>')
        rc = f' class="{row_classes[i]}"' if row_classes else ""
        rows.append(f"<tr{rc}>{''.join(cells)}</tr>")
    return f"<table><thead><tr>{head}</tr></thead><tbody>{''.join(rows)}</tbody></table>"


def image(path) -> str:
    """A PNG as an inline image (a data URI), so the page needs no other file."""
    data = base64.b64encode(Path(path).read_bytes()).decode("ascii")
    return f'<img src="data:image/png;base64,{data}" alt="{html.escape(Path(path).name)}">'


def caption(text: str) -> str:
    return f'<p class="caption">{html.escape(text)}</p>'


def write_page(path, title: str, body: str) -> None:
    """A complete HTML page, written atomically."""
    page = (
        f'<!DOCTYPE html>\n<html><head><meta charset="utf-8"><title>{html.escape(title)}</title>'
        f"<style>{_STYLE}</style></head><body><h1>{html.escape(title)}</h1>\n{body}\n</body></html>\n"
    )
    with atomic_path(path) as tmp:
        tmp.write_text(page)
