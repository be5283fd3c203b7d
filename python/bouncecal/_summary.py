"""The short summaries that repr() and notebooks show of a Result, Table or Calibration.

A result holds the whole JSON (a 42-impact analysis is some 15 000 characters of it), so its
repr is a summary instead: what kind of result it is, its key figures (a fit's parameters with
their interval, an analysis' impacts and each sequence's eta-bar), its scalar fields, the sizes
of what it holds and the list of its fields, within LIMIT characters as text and as HTML.
``result.to_json()`` and the fields themselves give everything.
"""

import html
import math
import numbers
import textwrap

import numpy

LIMIT = 2000  # characters, of the text and of the HTML
_SHOWN_ROWS = 3  # a Table's first rows in its HTML
_SHOWN_COLUMNS = 8
_SHOWN_SEQUENCES = 4
_WIDTH = 100  # columns of the text, as the project's other text


def sections_of(result):
    """(title, [(label, text), ...]) summarising a Result."""
    from ._result import Table  # the classes import this module

    if isinstance(result, Table):
        return _table_sections(result)
    title = f"bouncecal.{type(result).__name__}"
    if isinstance(result.get("format"), str):
        title += f" {result['format']}"
    sections = []
    if isinstance(result.get("file"), str):
        sections.append(("file", result["file"]))
    sections += _fitted_parameters(result)
    sections += _warnings(result)
    sections += _analysis(result)
    sections += _contact_law(result)
    shown = {"format", "file"}
    scalars = [f"{key}={_format(value)}" for key, value in result.items()
               if key not in shown and _is_scalar(value)]
    if scalars:
        sections.append(("scalars", ", ".join(scalars)))
    contents = [f"{key}: {_size(value)}" for key, value in result.items()
                if not _is_scalar(value)]
    if contents:
        sections.append(("holds", ", ".join(contents)))
    sections.append((f"fields ({len(result)})", ", ".join(result) or "(none)"))
    return title, sections


def text(result):
    """The repr: the title and one line per section, at most LIMIT characters."""
    title, sections = sections_of(result)
    return _fit(title, sections, _render_text)


def html_text(result):
    """The notebook display: the title and a table of the sections, at most LIMIT characters."""
    from ._result import Table

    title, sections = sections_of(result)
    preview = _table_preview(result) if isinstance(result, Table) else ""
    return _fit(title, sections, lambda t, s: _render_html(t, s, preview))


def _render_text(title, sections):
    lines = [f"<{title}"] + [textwrap.fill(f"{label}: {value}", width=_WIDTH, initial_indent="  ",
                                           subsequent_indent="      ", break_long_words=False,
                                           break_on_hyphens=False)
                             for label, value in sections]
    return "\n".join(lines) + ">"


def _render_html(title, sections, preview):
    cell = 'style="text-align:left;vertical-align:top"'
    rows = "".join(f"<tr><th {cell}>{html.escape(label)}</th><td {cell}>{html.escape(value)}"
                   "</td></tr>" for label, value in sections)
    return (f"<div><b>{html.escape(title)}</b><table>{rows}</table>{preview}</div>")


def _fit(title, sections, render):
    """render(title, sections), the longest section halved until it is within LIMIT."""
    sections = list(sections)
    rendered = render(title, sections)
    while len(rendered) > LIMIT:
        longest = max(range(len(sections)), key=lambda i: len(sections[i][1]), default=None)
        if longest is None or len(sections[longest][1]) <= 1:
            if not sections:
                return rendered[:LIMIT - 1] + "…"
            sections.pop()
        else:
            label, value = sections[longest]
            sections[longest] = (label, value[:len(value) // 2].rstrip(", ") + " …")
        rendered = render(title, sections)
    return rendered


def _fitted_parameters(result):
    """A fit's parameters with their confidence interval (calibrate, a law comparison's fits)."""
    fitted = result.get("fitted_parameters")
    if not isinstance(fitted, list):
        return []
    intervals = result.get("confidence_interval") or {}
    level = (result.get("uncertainty") or {}).get("confidence_level")
    sections = []
    for parameter in fitted:
        name = parameter.get("name")
        value = f"{_format(parameter.get('value'))}"
        unit = parameter.get("unit")
        if unit and unit != "1":
            value += f" {unit}"
        interval = intervals.get(name)
        if interval is not None and len(interval) == 2:
            percent = f"{100 * level:g} % " if isinstance(level, numbers.Real) else ""
            value += f", {percent}interval [{_format(interval[0])}, {_format(interval[1])}]"
        if parameter.get("at_bound"):
            value += " (at a bound of its range)"
        sections.append((str(name), value))
    return sections


def _warnings(result):
    """A fit's warnings, with the options they name spelt as this module's keywords."""
    from ._bouncecal import _with_keywords

    warnings = result.get("warnings")
    if not isinstance(warnings, list):
        return []
    return [("warning", _with_keywords(warning)) for warning in warnings if isinstance(warning, str)]


def _analysis(result):
    """An analysis' impacts and each bounce sequence's eta-bar."""
    from ._result import Table

    impacts, sequences = result.get("impacts"), result.get("sequences")
    if not isinstance(impacts, Table) or not isinstance(sequences, list):
        return []
    rejected = result.get("rejected_events")
    counts = f"{len(impacts)} impacts in {_plural(len(sequences), 'sequence')}"
    if isinstance(rejected, Table):
        counts += f", {_plural(len(rejected), 'rejected event')}"
    sections = [("impacts", counts)]
    for index, sequence in enumerate(sequences[:_SHOWN_SEQUENCES]):
        onsets = sequence.get("onsets_s")
        line = f"{len(onsets) if onsets is not None else '?'} impacts"
        mean = sequence.get("energy_loss_mean_first_n")
        if isinstance(mean, numbers.Real):
            sigma = sequence.get("energy_loss_mean_first_n_uncertainty")
            line += (f", eta-bar of the first {sequence.get('first_n')} = {_format(mean)}"
                     f" ± {_format(sigma, digits=2)}")
        else:
            line += ", too few impacts for eta-bar"
        if sequence.get("drop_height_m") is not None:
            line += f", drop height {_format(sequence['drop_height_m'])} m"
        sections.append((f"sequence {index}", line))
    if len(sequences) > _SHOWN_SEQUENCES:
        sections.append(("…", f"{len(sequences) - _SHOWN_SEQUENCES} more sequences"))
    return sections


def _contact_law(result):
    """A material card's or a drop's law with its parameters."""
    law = result.get("contact_law")
    if not isinstance(law, dict) or "fitted_parameters" in result:
        return []
    parameters = law.get("parameters") or {}
    values = ", ".join(f"{key}={_format(value)}" for key, value in parameters.items())
    return [("contact_law", f"{law.get('law')}" + (f" ({values})" if values else ""))]


def _table_sections(table):
    size = f"{_plural(len(table), 'row')} × {_plural(len(table.keys()), 'column')}"
    title = f"bouncecal.Table of {size}"
    columns = []
    for key, column in table.items():
        dtype = column.dtype if isinstance(column, numpy.ndarray) else "str"
        columns.append(f"{key} ({dtype})")
    return title, [("columns", ", ".join(columns) or "(none)")]


def _table_preview(table):
    """The first rows of a Table as an HTML table, a few columns wide."""
    keys = list(table.keys())[:_SHOWN_COLUMNS]
    if not keys or len(table) == 0:
        return ""
    header = "".join(f"<th>{html.escape(key)}</th>" for key in keys)
    rows = ""
    for i in range(min(len(table), _SHOWN_ROWS)):
        rows += "<tr>" + "".join(f"<td>{html.escape(_format(table[key][i]))}</td>"
                                 for key in keys) + "</tr>"
    more = len(table) - _SHOWN_ROWS
    tail = f"<p>… {_plural(more, 'more row')}</p>" if more > 0 else ""
    return f"<table><tr>{header}</tr>{rows}</table>{tail}"


def _is_scalar(value):
    return value is None or isinstance(value, (str, bool, numbers.Number))


def _size(value):
    from ._result import Table

    if isinstance(value, Table):
        return _plural(len(value), "row")
    if isinstance(value, numpy.ndarray):
        return "array " + "×".join(map(str, value.shape)) if value.ndim > 1 else (
            f"array of {value.size}")
    if isinstance(value, dict):
        return _plural(len(value), "field")
    if isinstance(value, (list, tuple)):
        return _plural(len(value), "entry", "entries")
    return type(value).__name__


def _format(value, digits=4):
    if isinstance(value, numpy.generic):
        value = value.item()
    if isinstance(value, bool) or value is None:
        return str(value)
    if isinstance(value, numbers.Integral):
        return str(value)
    if isinstance(value, numbers.Real):
        return f"{value:.{digits}g}" if math.isfinite(value) else str(value)
    if isinstance(value, str):
        return repr(value) if len(value) <= 60 else repr(value[:57]) + "…"
    return str(value)


def _plural(count, noun, plural=None):
    return f"{count} {noun if count == 1 else (plural or noun + 's')}"
