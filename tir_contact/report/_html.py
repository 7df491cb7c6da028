"""The HTML pieces every report page shares: escaping, links, tables, the page frame.

Plain HTML and CSS with relative links; the one inline script sorts a table when its
header is clicked (nothing is fetched from anywhere, the page works offline).
"""

from __future__ import annotations

import html
import math
from collections.abc import Iterable, Sequence
from urllib.parse import quote

__all__ = ["Cell", "esc", "fmt", "link", "page", "table"]

#: The stylesheet of every report page.
CSS = """
body{font:14px/1.4 system-ui,sans-serif;margin:1.5em;color:#222;max-width:1400px}
h1{font-size:1.5em;margin:0 0 .3em}h2{font-size:1.2em;margin:0}h3{font-size:1em;margin:.8em 0 .3em}
table{border-collapse:collapse;margin:.5em 0}td,th{border:1px solid #ccc;padding:2px 6px}
th{background:#eee;text-align:left}td.num{text-align:right;font-variant-numeric:tabular-nums}
table.sortable th{cursor:pointer;user-select:none}
table.sortable th[data-dir=asc]::after{content:" \\25B2"}
table.sortable th[data-dir=desc]::after{content:" \\25BC"}
.failed,.interrupted{background:#fdd}.partial{background:#ffe3b3}.warned{background:#fff6cc}
.card{border:1px solid #bbb;border-radius:6px;padding:.8em;margin:1em 0}
.card .thumbs img{margin-right:6px;border:1px solid #999;background:#000}
.muted{color:#666}.warn{color:#8a5a00}.err{color:#a00}
ul.warnings{margin:.3em 0 .3em 1.2em;padding:0}
img.plot{max-width:100%;height:auto}
"""

#: Sorts a ``table.sortable`` by the clicked column: by ``data-v`` when a cell has one,
#: numbers as numbers, empty cells last.
SORT_JS = """
document.querySelectorAll('table.sortable').forEach(function(t){
 t.querySelectorAll('th').forEach(function(th,i){th.addEventListener('click',function(){
  var asc=th.dataset.dir!=='asc';
  t.querySelectorAll('th').forEach(function(h){delete h.dataset.dir;});
  th.dataset.dir=asc?'asc':'desc';
  function key(r){var c=r.cells[i];var v=c.dataset.v!==undefined?c.dataset.v:c.textContent;
   var n=parseFloat(v);return v===''?null:(isNaN(n)?v.toLowerCase():n);}
  var rows=Array.prototype.slice.call(t.tBodies[0].rows);
  rows.sort(function(a,b){var x=key(a),y=key(b);
   if(x===null||y===null){return x===y?0:(x===null?1:-1);}
   if(typeof x!==typeof y){x=String(x);y=String(y);}
   var o=x<y?-1:(x>y?1:0);return asc?o:-o;});
  rows.forEach(function(r){t.tBodies[0].appendChild(r);});
 });});
});
"""


def esc(text: object) -> str:
    """HTML-escaped text."""
    return html.escape(str(text), quote=True)


def fmt(value: object, digits: int = 4) -> str:
    """A number with `digits` significant digits (empty for None or NaN).

    >>> fmt(463.91908), fmt(float("nan")), fmt(None), fmt(0.000123456)
    ('463.9', '', '', '0.0001235')
    """
    if value is None:
        return ""
    try:
        x = float(value)  # type: ignore[arg-type]
    except (TypeError, ValueError):
        return str(value)
    if not math.isfinite(x):
        return ""
    return f"{x:.{digits}g}"


def link(href: str, text: str) -> str:
    """An ``<a>`` to the relative path `href` (quoted for a URL)."""
    return f'<a href="{esc(quote(href, safe="/#"))}">{esc(text)}</a>'


class Cell:
    """A table cell: its HTML, an optional sort value and classes."""

    __slots__ = ("cls", "html", "sort")

    def __init__(self, html_text: str, sort: object = None, cls: str = "") -> None:
        self.html, self.sort, self.cls = html_text, sort, cls


def table(header: Sequence[str], rows: Iterable[Sequence[Cell | str]], *,
          sortable: bool = False, row_classes: Sequence[str] | None = None) -> str:
    """An HTML table; plain strings are escaped, :class:`Cell` s are used as given."""
    out = [f'<table{" class=sortable" if sortable else ""}><thead><tr>']
    out += [f"<th>{esc(h)}</th>" for h in header]
    out.append("</tr></thead><tbody>")
    for k, row in enumerate(rows):
        cls = row_classes[k] if row_classes else ""
        out.append(f'<tr class="{cls}">' if cls else "<tr>")
        for c in row:
            if isinstance(c, Cell):
                v = "" if c.sort is None else f' data-v="{esc(c.sort)}"'
                kind = f' class="{c.cls}"' if c.cls else ""
                out.append(f"<td{kind}{v}>{c.html}</td>")
            else:
                out.append(f"<td>{esc(c)}</td>")
        out.append("</tr>")
    out.append("</tbody></table>")
    return "".join(out)


def page(title: str, body: str, *, script: bool = False) -> str:
    """A whole HTML page: the stylesheet, `body`, the sort script when asked."""
    js = f"<script>{SORT_JS}</script>" if script else ""
    return (f'<!DOCTYPE html>\n<html lang="en"><head><meta charset="utf-8">'
            f'<meta name="viewport" content="width=device-width, initial-scale=1">'
            f"<title>{esc(title)}</title><style>{CSS}</style></head>"
            f"<body>{body}{js}</body></html>\n")
