"""Per-row views of results: an analysis as one row per impact (the rows of `bouncecal analyze
--csv`) and Tables, as records or as pandas DataFrames.

pandas is imported only when a DataFrame is asked for: the module does not need it otherwise.
"""

import math

import numpy

# The columns of `bouncecal analyze --csv` (calibrate::AnalysisCsv), in its order.
IMPACT_COLUMNS = (
    "file", "channel", "sequence", "k", "onset_s", "onset_uncertainty_s", "peak_dbfs",
    "interval_s", "bounce_height_m", "restitution", "restitution_uncertainty", "energy_loss",
    "energy_loss_uncertainty", "residual_only", "timed_from_response")
# Column types of the DataFrame: counts that are None for an impact in no sequence are pandas'
# nullable Int64 (<NA>), so they stay integers whatever the recording.
_DTYPES = {"channel": "int64", "sequence": "Int64", "k": "Int64", "residual_only": "bool",
           "timed_from_response": "bool"}


def impact_rows(analysis):
    """One dict per detected impact, in time order, with IMPACT_COLUMNS: its sequence (None when
    in none), k (1-based position within the sequence, as eta_k is numbered; None when in no
    sequence), its onset and peak, the flight after it and, where the sequence gives them, e_k
    and eta_k with their uncertainties (None otherwise)."""
    impacts = analysis["impacts"]
    sequences = analysis["sequences"]
    seen = [0] * len(sequences)  # impacts of each sequence met so far
    rows = []
    for i in range(len(impacts)):
        row = dict.fromkeys(IMPACT_COLUMNS)
        row.update(file=analysis.get("file"), channel=int(analysis["channel"]),
                   onset_s=float(impacts["onset_s"][i]),
                   onset_uncertainty_s=float(impacts["onset_uncertainty_s"][i]),
                   peak_dbfs=float(impacts["peak_dbfs"][i]),
                   residual_only=bool(impacts["residual_only"][i]),
                   timed_from_response=bool(impacts["timed_from_response"][i]))
        sequence_number = impacts["sequence"][i]
        if not math.isnan(sequence_number):
            s = int(sequence_number)
            position = seen[s]
            seen[s] += 1
            sequence = sequences[s]
            row.update(sequence=s, k=position + 1)
            if position < len(sequence["intervals_s"]):
                row.update(interval_s=float(sequence["intervals_s"][position]),
                           bounce_height_m=float(sequence["bounce_height_m"][position]))
            matches = numpy.flatnonzero(sequence["restitution_impact_index"] == position)
            if matches.size:
                j = int(matches[0])
                for column in ("restitution", "restitution_uncertainty", "energy_loss",
                               "energy_loss_uncertainty"):
                    row[column] = float(sequence[column][j])
        rows.append(row)
    return rows


def impact_frame(analysis):
    """impact_rows(analysis) as a pandas DataFrame (float columns NaN where a row has None)."""
    pandas = _pandas()
    frame = pandas.DataFrame(impact_rows(analysis), columns=list(IMPACT_COLUMNS))
    for column in IMPACT_COLUMNS[1:]:  # all but the file name
        frame[column] = frame[column].astype(_DTYPES.get(column, "float64"))
    return frame


def table_frame(table):
    """A Table's columns as a DataFrame, one row per event; a 2-D column (a position per
    particle) becomes one column per component, NAME_0, NAME_1, ..."""
    pandas = _pandas()
    columns = {}
    for key, column in table.items():
        if isinstance(column, numpy.ndarray) and column.ndim == 2:
            for component in range(column.shape[1]):
                columns[f"{key}_{component}"] = column[:, component]
        else:
            columns[key] = column
    return pandas.DataFrame(columns)


def _pandas():
    try:
        import pandas
    except ImportError as error:
        raise ImportError(
            "to_dataframe() needs pandas (Debian: apt-get install python3-pandas; pip: "
            "pip install pandas); records() gives the same rows without it") from error
    return pandas
