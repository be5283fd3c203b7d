# Type stubs of the bouncecal package (PEP 561; py.typed says they are there). The functions'
# keywords, their kinds and which have defaults are those of the extension, checked by
# python/tests/test_signatures.py; the defaults themselves are the C++ options structs' and show
# in inspect.signature(bouncecal.analyze) and help(). Results name the fields every result of
# their kind has; a Result reads any other JSON field as an attribute (Any).
import os
from typing import Any, Dict, List, Mapping, Optional, Sequence, Tuple, Union

import numpy
import numpy.typing
import pandas

__version__: str

_PathLike = Union[str, os.PathLike[str]]
# A law by name ("walton-braun") or as a card's contact_law {"law": ..., "parameters": ...}.
_Law = Union[str, Mapping[str, Any]]

class Error(Exception):
    exit_status: int

class InputError(Error, ValueError): ...
class ConfigError(Error, ValueError): ...
class OutputError(Error, OSError): ...
class CheckFailedError(Error): ...

class Result(Dict[str, Any]):
    def __getattr__(self, name: str) -> Any: ...
    def to_dict(self) -> Dict[str, Any]: ...
    def to_json(self, indent: Optional[int] = 2) -> str: ...
    def _repr_html_(self) -> str: ...

class Table(Result):
    def __len__(self) -> int: ...
    def records(self) -> List[Result]: ...
    def to_dict(self) -> List[Dict[str, Any]]: ...  # type: ignore[override]
    def to_dataframe(self) -> pandas.DataFrame: ...

class Analysis(Result):
    file: Optional[str]
    sample_rate_hz: int
    channel: int
    duration_s: float
    # Columns: onset_s, onset_uncertainty_s, peak_dbfs, rise_db, ringing_novelty_db, snr_db,
    # sequence (float64), residual_only, timed_from_response (bool).
    impacts: Table
    rejected_events: Table  # time_s, reason
    periodic_sound: Optional[Result]  # period_s, impacts (docs/json.md)
    sequences: List[Result]  # onsets_s, intervals_s, restitution, energy_loss, ... (numpy arrays)
    drop_height_m: Optional[float]
    gravity_mps2: float
    def records(self) -> List[Result]: ...
    def to_dataframe(self) -> pandas.DataFrame: ...

class Calibration(Result):
    format: str
    law: str
    contact_law: Result
    parameters: Result  # {name: value} of every parameter of the law
    fitted_parameters: List[Result]
    confidence_interval: Result  # {name: array [lower, upper]}
    uncertainty: Result
    analytic: Result
    sequences: List[Result]  # source, drop_height_m, measured, simulated_onsets_s, simulated
    warnings: List[str]
    def card(self, created_at: Optional[int] = None) -> Result: ...
    def write_card(self, path: _PathLike, created_at: Optional[int] = None) -> Result: ...

def analyze(
    recording: Union[_PathLike, numpy.typing.ArrayLike],
    *,
    drop_height_m: Optional[float] = ...,
    drop_height_uncertainty_m: float = ...,
    gravity_mps2: float = ...,
    first_n: int = ...,
    channel: Optional[int] = ...,
    sample_rate_hz: Optional[float] = ...,
    band_low_hz: float = ...,
    band_high_hz: float = ...,
    rise_threshold_db: float = ...,
    rise_lookback_ms: float = ...,
    min_snr_db: float = ...,
    min_gap_ms: float = ...,
    ringing_residual: bool = ...,
    frame_ms: float = ...,
    max_interval_s: float = ...,
    min_ratio: float = ...,
    max_ratio: float = ...,
    ratio_step_tolerance: float = ...,
    chatter_interval_ms: float = ...,
    min_impacts: int = ...,
    max_chance_alignment: float = ...,
) -> Analysis: ...

def simulate_drop(
    law: _Law = ...,
    parameters: Optional[Mapping[str, float]] = ...,
    *,
    ball: Optional[str] = ...,
    diameter_m: Optional[float] = ...,
    density_kg_per_m3: Optional[float] = ...,
    mass_kg: Optional[float] = ...,
    drop_height_m: float = ...,
    gravity_mps2: float = ...,
    integrator: str = ...,
    time_step_s: Optional[float] = ...,
    steps_per_contact: float = ...,
    allow_unstable_step: bool = ...,
    fixed_step_grid: bool = ...,
    locate_contact_events: bool = ...,
    drag: bool = ...,
    drag_coefficient: float = ...,
    air_density_kg_per_m3: float = ...,
    max_impacts: int = ...,
    max_time_s: float = ...,
    rest_flight_s: float = ...,
    rest_contact_factor: float = ...,
    trajectory_interval_s: float = ...,
) -> Result: ...

# One input, or a list of them, fitted jointly.
_CalibrationInput = Union[_PathLike, Analysis, numpy.typing.ArrayLike]

def calibrate(
    inputs: Union[_CalibrationInput, Sequence[_CalibrationInput]],
    *,
    law: _Law = ...,
    parameters: Optional[Mapping[str, float]] = ...,
    fitted_parameters: List[str] = ...,
    ranges: Optional[Mapping[str, Union[Tuple[float, float], Tuple[float, float, bool]]]] = ...,
    ball: Optional[str] = ...,
    diameter_m: Optional[float] = ...,
    density_kg_per_m3: Optional[float] = ...,
    mass_kg: Optional[float] = ...,
    drop_height_m: Union[float, Sequence[float], None] = ...,
    drop_height_uncertainty_m: Union[float, Sequence[float]] = ...,
    contact_duration_s: Optional[float] = ...,
    gravity_mps2: float = ...,
    integrator: str = ...,
    time_step_s: Optional[float] = ...,
    steps_per_contact: Optional[float] = ...,
    fixed_step_grid: bool = ...,
    drag: bool = ...,
    drag_coefficient: float = ...,
    air_density_kg_per_m3: float = ...,
    objective: str = ...,
    first_n: Optional[int] = ...,
    max_intervals: int = ...,
    optimizer: str = ...,
    max_evaluations: int = ...,
    global_evaluations: int = ...,
    confidence_level: float = ...,
    threads: int = ...,
    analytic_check: bool = ...,
    onset_uncertainty_s: float = ...,
) -> Calibration: ...

def pack(
    scene: Union[_PathLike, Mapping[str, Any]],
    *,
    threads: int = ...,
    duration_s: Optional[float] = ...,
    skin_diameters: float = ...,
    min_skin_diameters: float = ...,
    allow_unstable_step: bool = ...,
    precision: str = ...,
) -> Result: ...

def export(
    material: Union[_PathLike, Mapping[str, Any]],
    engine: str = ...,
    output_dir: Optional[_PathLike] = ...,
    *,
    drop_height_m: Optional[float] = ...,
    gravity_mps2: float = ...,
    time_step_s: Optional[float] = ...,
    max_step_error: float = ...,
    bounces: int = ...,
    scene: Union[_PathLike, Mapping[str, Any], None] = ...,
    processes: int = ...,
) -> Result: ...

def export_check(folder: _PathLike, *, max_gravity_effect: float = ...) -> Result: ...
