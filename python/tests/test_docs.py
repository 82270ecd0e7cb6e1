"""The numpydoc examples in the docstrings run (doctests)."""

import doctest
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
        for cls in (penedge.Block, penedge.BlockSystem, penedge.PairContact):
            tests += finder.find(cls, f"penedge.{cls.__name__}")
        functions = (penedge.detect_pair, penedge.generate, penedge.paper_example)
        for function in (*functions, penedge.paper_table3):
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
