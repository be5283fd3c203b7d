"""bouncecal for Python: DEM contact damping calibrated from the sound of a bouncing ball.

Thin bindings over the C++ libraries, one function per command of the ``bouncecal`` command line:

    analyze(recording, ...)       impacts, bounce sequences, e_k, eta_k    (bouncecal analyze)
    simulate_drop(law, ...)       a single-ball DEM drop                    (bouncecal simulate drop)
    calibrate(inputs, ...)        fit a law's damping; .card(), .write_card (bouncecal calibrate)
    pack(scene, ...)              a multi-particle packing scene            (bouncecal pack)
    export(material, ...)         LAMMPS / LIGGGHTS decks of a card         (bouncecal export)
    export_check(folder)          check an engine's run of the drop deck    (bouncecal export-check)

Each returns a Result, a dict with the keys of the command's JSON that also reads them as
attributes, numbers in sequence as numpy arrays (see bouncecal._result); analyze's Analysis and
every Table also give rows (records(), to_dataframe()). Problems raise the exceptions below with
the library's one-line message. docs/python.md has a worked example.
"""

from . import _bouncecal
from ._bouncecal import __version__
from ._errors import CheckFailedError, ConfigError, Error, InputError, OutputError
from ._result import Analysis, Calibration, Result, Table
from ._signatures import with_signature

# The extension's functions with signatures inspect.signature() reads (bouncecal._signatures).
analyze = with_signature(_bouncecal.analyze, returns=Analysis)
simulate_drop = with_signature(_bouncecal.simulate_drop, returns=Result)
calibrate = with_signature(_bouncecal.calibrate, returns=Calibration)
pack = with_signature(_bouncecal.pack, returns=Result)
export = with_signature(_bouncecal.export, returns=Result)
export_check = with_signature(_bouncecal.export_check, returns=Result)
del with_signature

__all__ = [
    "__version__",
    "analyze",
    "calibrate",
    "export",
    "export_check",
    "pack",
    "simulate_drop",
    "Analysis",
    "Calibration",
    "Result",
    "Table",
    "Error",
    "InputError",
    "ConfigError",
    "OutputError",
    "CheckFailedError",
]
