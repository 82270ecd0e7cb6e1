"""The type stubs _core.pyi agree with the compiled module: mypy's stubtest (names,
signatures, properties, final classes, types of constants), and independent checks of
names and parameters by the standard library."""

import ast
import inspect
import subprocess
import sys
from pathlib import Path

import pytest

import penedge
import penedge._core as core

STUB = Path(core.__file__).with_name("_core.pyi")
if not STUB.exists():  # an editable install keeps the stub in the source tree
    STUB = Path(penedge.__file__).with_name("_core.pyi")


def stub_tree():
    return ast.parse(STUB.read_text(encoding="utf-8"))


def stub_names():
    names = {}
    for node in stub_tree().body:
        if isinstance(node, ast.ClassDef | ast.FunctionDef):
            names[node.name] = node
        elif isinstance(node, ast.AnnAssign):
            names[node.target.id] = node
        elif isinstance(node, ast.Assign):
            names.update({t.id: node for t in node.targets})
    return names


def public(names):
    return {n for n in names if not n.startswith("_")} | ({"__version__"} & set(names))


def test_every_public_name_of_the_module_is_in_the_stub():
    assert public(dir(core)) - set(stub_names()) == set()


def test_every_public_name_of_the_stub_is_in_the_module():
    assert public(stub_names()) - set(dir(core)) == set()


def test_every_public_member_of_each_class_is_in_the_stub():
    stubs = stub_names()
    for name in dir(core):
        cls = getattr(core, name)
        if not inspect.isclass(cls) or issubclass(cls, BaseException):
            continue
        in_stub = {n.name for n in stubs[name].body if isinstance(n, ast.FunctionDef)}
        members = {m for m in vars(cls) if not m.startswith("_")}
        assert members - in_stub == set(), name
        assert {m for m in in_stub if not m.startswith("_")} - members == set(), name


def test_function_parameters_match():
    stubs = stub_names()
    names = (
        "detect_pair",
        "generate",
        "paper_example",
        "paper_table3",
        "paper_example_planes",
        "write_pvd",
    )
    for name in names:
        runtime = list(inspect.signature(getattr(core, name)).parameters)
        assert [a.arg for a in stubs[name].args.args] == runtime, name


def test_package_exports_everything_public():
    assert sorted(penedge.__all__) == sorted(public(dir(core)))
    assert (Path(penedge.__file__).parent / "py.typed").exists()


def test_mypy_stubtest_passes(tmp_path):
    pytest.importorskip("mypy.stubtest")
    # In a scratch folder: mypy leaves its cache in the working directory.
    out = subprocess.run(
        [sys.executable, "-m", "mypy.stubtest", "--concise", "penedge._core"],
        cwd=tmp_path,
        capture_output=True,
        text=True,
        check=False,
        timeout=300,
    )
    assert out.returncode == 0, out.stdout + out.stderr
