"""Python functions with introspectable signatures over the extension's functions.

pybind11 2.10 gives a compiled function its signature only as the first line of its docstring,
so ``inspect.signature`` (and with it notebooks' completion and ``help``'s header) cannot read
it. ``with_signature`` wraps such a function in a Python function whose ``__signature__`` is
that line, parsed: the keywords, their kinds and the defaults pybind11 took from the C++ options
structs, so they stay the command line's defaults without being written down a second time.
"""

import ast
import inspect
import os
import typing

# The names pybind11 2.10 writes in its type descriptions.
_ANNOTATION_NAMES = {"Optional": typing.Optional, "List": typing.List, "Dict": typing.Dict,
                     "Union": typing.Union, "os": os, "float": float, "int": int, "bool": bool,
                     "str": str}


def native_signature(function):
    """The signature in the first line of a pybind11 function's docstring; ValueError when the
    line is not one (e.g. an overloaded function)."""
    line = (function.__doc__ or "").split("\n", 1)[0]
    try:
        tree = ast.parse(f"def {line}: pass")
    except SyntaxError as error:
        raise ValueError(f"not a signature line: {line!r}") from error
    definition = tree.body[0]
    if not isinstance(definition, ast.FunctionDef) or definition.name != function.__name__:
        raise ValueError(f"not the signature of {function.__name__}: {line!r}")
    arguments = definition.args

    def parameter(node, kind, default=inspect.Parameter.empty):
        if default is not inspect.Parameter.empty:
            default = ast.literal_eval(default)
        return inspect.Parameter(node.arg, kind, default=default,
                                 annotation=_annotation(node.annotation))

    positional = arguments.posonlyargs + arguments.args
    defaults = [inspect.Parameter.empty] * (len(positional) - len(arguments.defaults))
    defaults += arguments.defaults
    parameters = [parameter(node, inspect.Parameter.POSITIONAL_ONLY, default)
                  for node, default in zip(arguments.posonlyargs, defaults)]
    parameters += [parameter(node, inspect.Parameter.POSITIONAL_OR_KEYWORD, default)
                   for node, default in zip(arguments.args, defaults[len(parameters):])]
    parameters += [parameter(node, inspect.Parameter.KEYWORD_ONLY,
                             inspect.Parameter.empty if default is None else default)
                   for node, default in zip(arguments.kwonlyargs, arguments.kw_defaults)]
    return inspect.Signature(parameters)


def _annotation(node):
    # `object` says nothing a reader can use; the stubs (__init__.pyi) give the accepted types.
    if node is None or (isinstance(node, ast.Name) and node.id == "object"):
        return inspect.Parameter.empty
    try:
        return eval(compile(ast.Expression(node), "<pybind11 signature>", "eval"),  # noqa: S307
                    {"__builtins__": {}}, dict(_ANNOTATION_NAMES))
    except Exception:  # a type pybind11 names that is not importable here: keep its text
        return ast.unparse(node)


def with_signature(native, returns):
    """A function that calls `native` with the same arguments and has its parsed signature,
    returning `returns`, and its docstring without the signature line."""
    signature = native_signature(native).replace(return_annotation=returns)

    def function(*args, **kwargs):
        # Binding first gives Python's own TypeError for a misspelt or missing keyword, naming
        # it, instead of pybind11's list of every accepted type.
        signature.bind(*args, **kwargs)
        return native(*args, **kwargs)

    function.__name__ = function.__qualname__ = native.__name__
    function.__module__ = "bouncecal"
    function.__signature__ = signature
    function.__doc__ = (native.__doc__ or "").split("\n", 1)[-1].strip("\n")
    return function
