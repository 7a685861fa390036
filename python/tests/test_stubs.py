"""cs123ray.pyi against the module (issue 52): every public name of the module in the stubs
and every name of the stubs in the module, each function's and method's parameters the
same (names, *args, **kwargs, which have defaults), and a docstring on every public
function, class, method and property. The stubs are found beside the module, where the
build and the install put them."""
import ast
import inspect
import os
import re

import pytest

cs123ray = pytest.importorskip("cs123ray")

# Jupyter's display hooks are public in all but their name.
DISPLAY_HOOK = re.compile(r"^_repr_\w+_$")


def is_public(name):
    return not name.startswith("_") or DISPLAY_HOOK.match(name) or name == "__init__"


def stub_tree():
    path = os.path.join(os.path.dirname(cs123ray.__file__), "cs123ray.pyi")
    assert os.path.exists(path), f"no cs123ray.pyi beside the module ({path})"
    with open(path, encoding="utf-8") as file:
        return ast.parse(file.read())


# ---------------------------------------------------------------------------------------
# Signatures as (name, kind, has_default) tuples; kind: "", "*" or "**" (whose names differ
# between the C++ module's *args/**kwargs and the stubs' *nodes/**fields, so are not compared).

def stub_signature(function, method):
    arguments = function.args
    positional = arguments.posonlyargs + arguments.args
    static = any(isinstance(d, ast.Name) and d.id == "staticmethod" for d in function.decorator_list)
    if method and not static:
        positional = positional[1:]  # self
    defaults = [False] * (len(positional) - len(arguments.defaults)) + [True] * len(arguments.defaults)
    signature = [(a.arg, "", d) for a, d in zip(positional, defaults)]
    if arguments.vararg:
        signature.append(("", "*", False))
    signature += [(a.arg, "", d is not None) for a, d in zip(arguments.kwonlyargs, arguments.kw_defaults)]
    if arguments.kwarg:
        signature.append(("", "**", False))
    return tuple(signature)


def split_top_level(text):
    parts, depth, current = [], 0, ""
    for character in text:
        if character in "([{":
            depth += 1
        elif character in ")]}":
            depth -= 1
        if character == "," and depth == 0:
            parts.append(current.strip())
            current = ""
        else:
            current += character
    if current.strip():
        parts.append(current.strip())
    return parts


def pybind_signatures(function, name):
    """The signatures a pybind11 function's docstring gives (several when overloaded)."""
    found = []
    for match in re.finditer(rf"^(?:\d+\. )?{re.escape(name)}\((.*)\) -> ", function.__doc__ or "", re.M):
        signature = []
        for parameter in split_top_level(match.group(1)):
            if parameter.strip() == "*":
                continue  # keyword-only from here: the stub's kwonlyargs say the same
            if parameter.startswith("**"):
                signature.append(("", "**", False))
            elif parameter.startswith("*"):
                signature.append(("", "*", False))
            else:
                parameter_name = parameter.split(":")[0].split("=")[0].strip()
                if parameter_name != "self":
                    signature.append((parameter_name, "", "=" in parameter))
        found.append(tuple(signature))
    return found


def module_signatures(function, name, method):
    """The signatures of a function of the module: a Python one's from inspect, a C++ one's
    (or a Python wrapper of one) from its pybind11 docstring."""
    try:
        signature = inspect.signature(function)
    except (TypeError, ValueError):
        found = pybind_signatures(function, name)
        assert found, f"{name}: no signature in its docstring: {function.__doc__!r}"
        return set(found)
    kinds = {inspect.Parameter.VAR_POSITIONAL: "*", inspect.Parameter.VAR_KEYWORD: "**"}
    parameters = list(signature.parameters.values())
    if method and parameters and parameters[0].name == "self":
        parameters = parameters[1:]
    return {tuple((("" if p.kind in kinds else p.name), kinds.get(p.kind, ""),
                   p.default is not inspect.Parameter.empty) for p in parameters)}


# ---------------------------------------------------------------------------------------

def stub_members(node):
    """A stub class's or module's functions (name -> set of signatures) and other names."""
    functions, others = {}, set()
    for item in node.body:
        if isinstance(item, ast.FunctionDef):
            decorators = {d.id if isinstance(d, ast.Name) else getattr(d, "attr", "") for d in item.decorator_list}
            if "property" in decorators or "setter" in decorators:
                others.add(item.name)
            else:
                functions.setdefault(item.name, set()).add(stub_signature(item, isinstance(node, ast.ClassDef)))
        elif isinstance(item, ast.AnnAssign):
            others.add(item.target.id)
        elif isinstance(item, ast.Assign):
            others.update(target.id for target in item.targets)
        elif isinstance(item, ast.ClassDef):
            others.add(item.name)
    return functions, others


def no_constructor(cls, member):
    """A class Python code does not construct (pybind11's __init__ that raises, a slot)."""
    return member == "__init__" and type(vars(cls)[member]).__name__ == "wrapper_descriptor"


def test_every_public_name_of_the_module_is_in_the_stubs_and_back():
    tree = stub_tree()
    functions, others = stub_members(tree)
    stubbed = set(functions) | others
    public = {name for name in dir(cs123ray) if not name.startswith("_")} | {"__version__"}
    missing = sorted(public - stubbed)
    assert not missing, f"cs123ray.pyi lacks {missing}"
    aliases = {"Vector", "PathText", "Dtype"}  # the stubs' own type aliases
    extra = sorted(stubbed - public - aliases)
    assert not extra, f"cs123ray.pyi names {extra}, which the module does not have"


def test_each_function_has_the_parameters_of_its_stub():
    tree = stub_tree()
    functions, _ = stub_members(tree)
    for name, signatures in functions.items():
        assert module_signatures(getattr(cs123ray, name), name, False) == signatures, \
            f"cs123ray.{name}'s parameters differ from cs123ray.pyi's"


def test_each_class_has_the_members_and_parameters_of_its_stub():
    tree = stub_tree()
    classes = {item.name: item for item in tree.body if isinstance(item, ast.ClassDef)}
    for name in dir(cs123ray):
        cls = getattr(cs123ray, name)
        if name.startswith("_") or not isinstance(cls, type):
            continue
        assert name in classes, f"cs123ray.pyi has no class {name}"
        functions, others = stub_members(classes[name])
        own = {member for member in vars(cls) if is_public(member) and not no_constructor(cls, member)}
        if issubclass(cls, BaseException):
            own = set()  # exceptions: their fields are set on each instance, stubbed as attributes
        missing = sorted(member for member in own if member not in functions and member not in others)
        assert not missing, f"cs123ray.pyi's {name} lacks {missing}"
        for member, signatures in functions.items():
            assert hasattr(cls, member), f"cs123ray.pyi's {name}.{member} is not in the module"
            if member == "__init__" and "__init__" not in vars(cls):
                continue
            assert module_signatures(getattr(cls, member), member, True) == signatures, \
                f"cs123ray.{name}.{member}'s parameters differ from cs123ray.pyi's"
        for member in others:
            assert hasattr(cls, member) or member in ("file", "line", "scene", "url", "port"), \
                f"cs123ray.pyi's {name}.{member} is not in the module"


def documentation(value, name):
    """A docstring without pybind11's signature lines."""
    text = inspect.getdoc(value) or ""
    lines = [line for line in text.splitlines()
             if not re.match(rf"^(\d+\. )?{re.escape(name)}\(.*\) -> ", line) and line != "Overloaded function."]
    return "\n".join(lines).strip()


def test_every_public_function_class_method_and_property_has_a_docstring():
    undocumented = []
    for name in dir(cs123ray):
        if name.startswith("_"):
            continue
        value = getattr(cs123ray, name)
        if callable(value) and not documentation(value, name):
            undocumented.append(name)
        if isinstance(value, type):
            for member, attribute in vars(value).items():
                if not is_public(member) or issubclass(value, BaseException) or no_constructor(value, member):
                    continue
                target = attribute.fget if isinstance(attribute, property) else attribute
                if isinstance(attribute, property) and attribute.__doc__:
                    continue
                if not documentation(target, member):
                    undocumented.append(f"{name}.{member}")
    assert cs123ray.__doc__
    assert not undocumented, f"no docstring: {undocumented}"


def test_the_check_finds_a_missing_name_and_a_changed_parameter():
    """The comparison can fail: a stub without Scene.outline, or with render's device renamed."""
    tree = stub_tree()
    scene = next(item for item in tree.body if isinstance(item, ast.ClassDef) and item.name == "Scene")
    functions, others = stub_members(scene)
    functions.pop("outline")
    assert "outline" in {m for m in vars(cs123ray.Scene) if is_public(m)} - set(functions) - others
    render = next(item for item in tree.body if isinstance(item, ast.FunctionDef) and item.name == "render")
    render.args.args[1].arg = "devices"
    assert module_signatures(cs123ray.render, "render", False) != {stub_signature(render, False)}
