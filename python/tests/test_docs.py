"""The documentation holds: the numpydoc examples in the docstrings and the examples of
docs/python.md and docs/contact-types.md run (doctests); the contact type pictures show what
penedge finds; docs/api.md is up to date with the docstrings, and every public name has one;
relative links and pictures of the Markdown pages exist."""

import doctest
import importlib.util
import re
import sys
from pathlib import Path

import pytest

import penedge
import penedge._core
import penedge.pictures.blocks
import penedge.pictures.contacts
import penedge.pictures.volumes

MODULES = [
    penedge,
    penedge._core,
    penedge.pictures.blocks,
    penedge.pictures.contacts,
    penedge.pictures.volumes,
]


@pytest.mark.parametrize("module", MODULES, ids=lambda m: m.__name__)
def test_docstring_examples(module):
    finder = doctest.DocTestFinder(exclude_empty=True)
    runner = doctest.DocTestRunner(optionflags=doctest.NORMALIZE_WHITESPACE)
    tests = finder.find(module, module.__name__)
    if module is penedge._core:
        classes = (penedge.Block, penedge.BlockSystem, penedge.PairContact, penedge.TimeSeries)
        for cls in classes:
            tests += finder.find(cls, f"penedge.{cls.__name__}")
        functions = (penedge.detect_pair, penedge.generate, penedge.paper_example)
        for function in (*functions, penedge.paper_table3, penedge.write_pvd):
            tests += finder.find(function, f"penedge.{function.__name__}")
    examples = 0
    for test in tests:
        examples += len(test.examples)
        runner.run(test)
    assert examples > 0
    assert runner.failures == 0, f"{runner.failures} doctest failures in {module.__name__}"


def test_python_tutorial():
    tutorial = Path(__file__).parents[2] / "docs" / "python.md"
    if not tutorial.exists():
        pytest.skip("docs/python.md is not installed with the package")
    result = doctest.testfile(
        str(tutorial), module_relative=False, optionflags=doctest.NORMALIZE_WHITESPACE
    )
    assert result.attempted > 10
    assert result.failed == 0


ROOT = Path(__file__).parents[2]


def load_tool(name):
    """A script of tools/ as a module (skips where the tests run without the repository)."""
    path = ROOT / "tools" / f"{name}.py"
    if not path.exists():
        pytest.skip("tools/ is not next to the tests")
    spec = importlib.util.spec_from_file_location(f"tools_{name}", path)
    module = importlib.util.module_from_spec(spec)
    sys.modules[spec.name] = module  # dataclasses look their module up
    spec.loader.exec_module(module)
    return module


def test_contact_types_guide():
    guide = ROOT / "docs" / "contact-types.md"
    if not guide.exists():
        pytest.skip("docs/ is not next to the tests")
    result = doctest.testfile(
        str(guide), module_relative=False, optionflags=doctest.NORMALIZE_WHITESPACE
    )
    assert result.attempted >= 5
    assert result.failed == 0


def test_each_contact_type_picture_shows_what_penedge_finds():
    pictures = load_tool("make_doc_pictures")
    pairs = pictures.pairs()
    assert [p.code for p in pairs] == [1, 2, 3, 4, 5, 6, 7]
    guide = (ROOT / "docs" / "contact-types.md").read_text(encoding="utf-8")
    for pair in pairs:
        for a, b in ((pair.a, pair.b), (pair.b, pair.a)):
            found = penedge.detect_pair(a, b)
            assert found.outcome == pair.name, pair.file
            assert found.type_code == pair.code, pair.file
        assert (ROOT / "docs" / "img" / pair.file).read_bytes()[:4] == b"\x89PNG", pair.file
        assert f"](img/{pair.file})" in guide, pair.file


def test_api_reference_is_up_to_date():
    reference = load_tool("api_reference")
    assert reference.undocumented() == []
    written = (ROOT / "docs" / "api.md").read_text(encoding="utf-8")
    assert written == reference.page(), "docs/api.md is stale: run python3 tools/api_reference.py"
    for name in penedge.__all__:
        assert f"### `{name}`" in written, name


def test_every_public_name_has_a_docstring():
    """Independent of the generator: classes, functions and their public members."""
    reference = load_tool("api_reference")
    listed = {
        name: reference.listed_attributes(getattr(penedge, name))
        for name in penedge.__all__
        if isinstance(getattr(penedge, name), type)
    }
    missing = []
    for name in penedge.__all__:
        obj = getattr(penedge, name)
        if callable(obj) and not (obj.__doc__ or "").strip():
            missing.append(name)
        if isinstance(obj, type) and not issubclass(obj, BaseException):
            for member in (m for m in vars(obj) if not m.startswith("_")):
                documented = (getattr(obj, member).__doc__ or "").strip()
                if not documented and member not in listed[name]:
                    missing.append(f"{name}.{member}")
    assert missing == []
    assert "pairs" in listed["SystemContacts"]  # the Attributes section is read


LINK = re.compile(r"\]\(([^)\s]+)\)")


@pytest.mark.parametrize("page", ["README.md", "CHANGELOG.md", "docs"])
def test_relative_links_and_pictures_exist(page):
    paths = sorted((ROOT / page).glob("*.md")) if page == "docs" else [ROOT / page]
    if not paths or not paths[0].exists():
        pytest.skip("the documentation is not next to the tests")
    checked = 0
    for path in paths:
        for target in LINK.findall(path.read_text(encoding="utf-8")):
            if re.match(r"[a-z]+:", target) or target.startswith("#"):
                continue  # a web address, or an anchor in the page
            file = (path.parent / target.split("#")[0]).resolve()
            assert file.exists(), f"{path.name}: {target}"
            checked += 1
    assert checked > 0 or page == "CHANGELOG.md"
