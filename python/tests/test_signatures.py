"""What a notebook and a type checker read of the package: signatures, stubs and the version."""

import ast
import importlib.util
import inspect
import os
import pathlib
import re
import subprocess
import sys

import pytest

import bouncecal
from conftest import SOURCE_DIR

FUNCTIONS = ["analyze", "simulate_drop", "calibrate", "pack", "export", "export_check"]
PACKAGE = pathlib.Path(bouncecal.__file__).parent
RETURNS = {"analyze": bouncecal.Analysis, "calibrate": bouncecal.Calibration}


def stub_functions():
    """{name: ast.FunctionDef} of the package's __init__.pyi, as installed beside the module."""
    tree = ast.parse((PACKAGE / "__init__.pyi").read_text())
    return {node.name: node for node in tree.body if isinstance(node, ast.FunctionDef)}


def stub_parameters(definition):
    """[(name, kind, has a default)] of a stub's def."""
    arguments = definition.args
    positional = arguments.posonlyargs + arguments.args
    defaults = [False] * (len(positional) - len(arguments.defaults)) + [True] * len(
        arguments.defaults)
    found = [(node.arg, inspect.Parameter.POSITIONAL_ONLY, default)
             for node, default in zip(arguments.posonlyargs, defaults)]
    found += [(node.arg, inspect.Parameter.POSITIONAL_OR_KEYWORD, default)
              for node, default in zip(arguments.args, defaults[len(found):])]
    found += [(node.arg, inspect.Parameter.KEYWORD_ONLY, default is not None)
              for node, default in zip(arguments.kwonlyargs, arguments.kw_defaults)]
    return found


@pytest.mark.parametrize("name", FUNCTIONS)
def test_every_public_function_has_a_signature_with_its_defaults_and_result_type(name):
    function = getattr(bouncecal, name)
    signature = inspect.signature(function)
    assert signature.return_annotation is RETURNS.get(name, bouncecal.Result)
    assert len(signature.parameters) >= 2
    assert function.__doc__ and not function.__doc__.startswith(name + "(")  # no signature line
    assert function.__module__ == "bouncecal"


def test_the_signature_states_the_command_lines_defaults():
    # The defaults come from the C++ options structs; these are the ones docs/python.md and
    # `bouncecal analyze --help` state, so a parse that lost or shifted one fails here.
    parameters = inspect.signature(bouncecal.analyze).parameters
    assert parameters["recording"].default is inspect.Parameter.empty
    assert parameters["recording"].kind is inspect.Parameter.POSITIONAL_OR_KEYWORD
    assert parameters["drop_height_m"].default is None
    assert parameters["drop_height_m"].kind is inspect.Parameter.KEYWORD_ONLY
    assert parameters["first_n"].default == 3 and parameters["gravity_mps2"].default == 9.81
    assert parameters["ringing_residual"].default is True
    calibrate = inspect.signature(bouncecal.calibrate).parameters
    assert calibrate["law"].default == "walton-braun"
    assert calibrate["objective"].default == "mean-energy-loss"
    assert calibrate["confidence_level"].default == 0.95


def test_a_misspelt_keyword_is_pythons_type_error_naming_it(steel_sample):
    with pytest.raises(TypeError, match="unexpected keyword argument 'drop_height'"):
        bouncecal.analyze(steel_sample, drop_height=0.2)
    with pytest.raises(TypeError, match="missing a required argument: 'recording'"):
        bouncecal.analyze()


@pytest.mark.parametrize("name", FUNCTIONS)
def test_the_stubs_declare_each_function_as_it_is(name):
    # Names, kinds and which keywords have defaults: a keyword added to a binding and not to
    # __init__.pyi fails here.
    definition = stub_functions()[name]
    runtime = [(p.name, p.kind, p.default is not inspect.Parameter.empty)
               for p in inspect.signature(getattr(bouncecal, name)).parameters.values()]
    assert stub_parameters(definition) == runtime
    returns = RETURNS.get(name, bouncecal.Result).__name__
    assert ast.unparse(definition.returns) == returns


def test_the_stubs_are_shipped_and_name_every_public_name():
    assert (PACKAGE / "py.typed").is_file()
    tree = ast.parse((PACKAGE / "__init__.pyi").read_text())
    declared = set()
    for node in tree.body:
        if isinstance(node, (ast.FunctionDef, ast.ClassDef)):
            declared.add(node.name)
        elif isinstance(node, ast.AnnAssign):
            declared.add(node.target.id)
    assert set(bouncecal.__all__) <= declared


def test_mypys_stubtest_finds_the_stubs_true_to_the_module(tmp_path):
    # stubtest imports the module and compares every name, signature and default-or-not with
    # __init__.pyi. pandas has no stubs of its own: its import is not this package's to check.
    if importlib.util.find_spec("mypy") is None:
        pytest.skip("mypy is not installed (Debian: python3-mypy)")
    config = tmp_path / "mypy.ini"
    config.write_text(f"[mypy]\nignore_missing_imports = True\ncache_dir = {tmp_path / 'cache'}\n")
    checked = subprocess.run(
        [sys.executable, "-m", "mypy.stubtest", "bouncecal", "--mypy-config-file", str(config)],
        capture_output=True, text=True, cwd=tmp_path, timeout=300,
        env={**os.environ, "PYTHONPATH": str(PACKAGE.parent)})  # the package these tests import
    assert checked.returncode == 0, checked.stdout[-3000:] + checked.stderr[-1000:]


def test_the_version_is_the_projects():
    project = re.search(r"project\(bouncecal VERSION ([0-9.]+)",
                        (SOURCE_DIR / "CMakeLists.txt").read_text())
    assert bouncecal.__version__ == project.group(1)


def test_the_version_is_the_commands(cli):
    assert cli.run("--version").stdout.split() == ["bouncecal", bouncecal.__version__]
