"""Write docs/api.md, the Python API reference, from the docstrings.

The names are the public ones (``__all__``) of ``penedge`` and ``penedge.pictures``; the
text is their docstrings (numpydoc), turned into Markdown; the signatures of the compiled
module come from its type stubs (``penedge/_core.pyi``, checked against the module by the
tests), the others from ``inspect``. Constants are documented by a docstring under their
line in the stubs, or a ``#:`` comment above it in the source.

    python3 tools/api_reference.py            # rewrite docs/api.md
    python3 tools/api_reference.py --check    # exit 1 if docs/api.md is not up to date

The tests (python/tests/test_docs.py) fail when docs/api.md differs from what this script
writes, or when a public name has no docstring. Standard library only (besides penedge).
"""

from __future__ import annotations

import argparse
import ast
import copy
import inspect
import re
import sys
from pathlib import Path

import penedge
import penedge._core
import penedge.pictures

ROOT = Path(__file__).resolve().parents[1]
OUTPUT = ROOT / "docs" / "api.md"
STUB = Path(penedge.__file__).with_name("_core.pyi")
MODULES = (penedge, penedge.pictures)

HEADER = """\
# Python API reference

Generated from the docstrings by `python3 tools/api_reference.py` (do not edit: the tests
check that this file is up to date). A guided tour with examples is in
[python.md](python.md); the contact types in [contact-types.md](contact-types.md).
"""

ENTRY_SECTIONS = {"Parameters", "Returns", "Raises", "Attributes", "Yields", "Other Parameters"}
ROLE = re.compile(r":(?:class|meth|func|data|exc|mod|attr):`~?([^`]+)`")


# -- what to document ---------------------------------------------------------------------


def stub_tree():
    return ast.parse(STUB.read_text(encoding="utf-8"))


def stub_entries():
    """The stub's top-level definitions by name, and the docstring under each assignment."""
    body = stub_tree().body
    nodes, notes = {}, {}
    for k, node in enumerate(body):
        if isinstance(node, ast.ClassDef | ast.FunctionDef):
            nodes[node.name] = node
        elif isinstance(node, ast.AnnAssign | ast.Assign):
            target = node.target if isinstance(node, ast.AnnAssign) else node.targets[0]
            name = target.id
            nodes[name] = node
            after = body[k + 1] if k + 1 < len(body) else None
            if (
                isinstance(after, ast.Expr)
                and isinstance(after.value, ast.Constant)
                and isinstance(after.value.value, str)
            ):
                notes[name] = after.value.value
    return nodes, notes


def source_comment(module, name):
    """The ``#:`` comment lines above ``name = ...`` in the source of `module`'s package."""
    for path in sorted(Path(module.__file__).parent.glob("*.py")):
        lines = path.read_text(encoding="utf-8").splitlines()
        for k, line in enumerate(lines):
            if re.match(rf"{re.escape(name)}\s*(:[^=]*)?=", line):
                comment = []
                j = k - 1
                while j >= 0 and lines[j].startswith("#:"):
                    comment.insert(0, lines[j][2:].strip())
                    j -= 1
                if comment:
                    return " ".join(comment)
    return None


def public_names(module):
    return sorted(module.__all__, key=lambda n: (n.startswith("_"), n.lower()))


def members(cls, stub_class):
    """The public members of a class: in the stub's order for compiled classes (so the
    order does not depend on the build), else in definition order."""
    if stub_class is not None:
        names = []
        for node in stub_class.body:
            public = isinstance(node, ast.FunctionDef) and not node.name.startswith("_")
            if public and node.name not in names:
                names.append(node.name)
        return names
    return [n for n in vars(cls) if not n.startswith("_")]


def listed_attributes(cls):
    """The names of the ``Attributes`` section of a class docstring (numpydoc): members
    documented there need no docstring of their own."""
    lines = inspect.cleandoc(cls.__doc__ or "").splitlines()
    names, inside = set(), False
    for line, following in zip(lines, [*lines[1:], ""], strict=True):
        if re.fullmatch(r"-{3,}", following.strip()):
            inside = line.strip() == "Attributes"
        elif inside and line and not line.startswith(" ") and not re.fullmatch(r"-{3,}", line):
            names.add(line.partition(" : ")[0].strip())
    return names


def own_doc(cls, member):
    """A member's own docstring, if any."""
    return (getattr(cls, member).__doc__ or "").strip()


def undocumented():
    """Public names (and public members of public classes) without a docstring."""
    _, notes = stub_entries()
    missing = []
    for module in MODULES:
        for name in public_names(module):
            obj = getattr(module, name)
            if inspect.isclass(obj) or callable(obj):
                if not (obj.__doc__ or "").strip():
                    missing.append(f"{module.__name__}.{name}")
                if inspect.isclass(obj) and not issubclass(obj, BaseException):
                    listed = listed_attributes(obj)
                    for member in (m for m in vars(obj) if not m.startswith("_")):
                        if not own_doc(obj, member) and member not in listed:
                            missing.append(f"{module.__name__}.{name}.{member}")
            elif name not in notes and source_comment(module, name) is None:
                missing.append(f"{module.__name__}.{name}")
    return missing


# -- signatures ---------------------------------------------------------------------------


def stub_arguments(function, drop_first):
    """The argument list of a stub function, as written in the stub (without `self` or
    `cls` when `drop_first`)."""
    args = copy.deepcopy(function.args)
    if drop_first:
        (args.posonlyargs or args.args).pop(0)
    return ast.unparse(args)


def stub_signature(name, function, owner=None):
    """``name(args) -> returns`` from a stub function (self / cls left out)."""
    static = any(ast.unparse(d) == "staticmethod" for d in function.decorator_list)
    arguments = stub_arguments(function, drop_first=owner is not None and not static)
    returns = f" -> {ast.unparse(function.returns)}" if function.returns else ""
    if function.name == "__new__":
        return f"{owner}({arguments})"
    return f"{name}({arguments}){returns}"


def is_property(function):
    return any(ast.unparse(d) == "property" for d in function.decorator_list)


# -- docstrings to Markdown ---------------------------------------------------------------


def inline(text):
    """reST roles and literals as Markdown code."""
    text = ROLE.sub(lambda m: f"`{m.group(1)}`", text)
    return text.replace("``", "`")


def markdown(doc):
    """A numpydoc docstring as Markdown: section titles bold, parameter entries as a list,
    doctest examples as Python code blocks, definition lists as lists."""
    lines = inspect.cleandoc(doc).splitlines()
    out, section, k = [], None, 0
    while k < len(lines):
        line = lines[k]
        following = lines[k + 1] if k + 1 < len(lines) else ""
        if line.strip() and re.fullmatch(r"-{3,}", following.strip()):
            section = line.strip()
            out += ["", f"**{section}**", ""]
            k += 2
            continue
        if line.startswith(">>>"):
            block = []
            while k < len(lines) and lines[k].strip():
                block.append(lines[k])
                k += 1
            out += ["```python", *block, "```"]
            continue
        if line.strip() and not line.startswith(" ") and following.startswith("    "):
            term, k = line.strip(), k + 1
            text = []
            while k < len(lines) and (lines[k].startswith("    ") or not lines[k].strip()):
                if not lines[k].strip() and not (
                    k + 1 < len(lines) and lines[k + 1].startswith("    ")
                ):
                    break
                text.append(lines[k].strip())
                k += 1
            out.append(entry(term, " ".join(t for t in text if t), section))
            continue
        if section in ENTRY_SECTIONS and line.strip() and not line.startswith(" "):
            out.append(entry(line.strip(), "", section))
            k += 1
            continue
        out.append(inline(line.strip() if line.startswith("    ") else line))
        k += 1
    return "\n".join(out).strip() + "\n"


def entry(term, text, section):
    """One list item: a parameter (``name : type``) or a term of a definition list."""
    if section in ENTRY_SECTIONS:
        name, colon, kind = term.partition(" : ")
        head = f"`{name}`" + (f" ({inline(kind)})" if colon else "")
    else:
        head = f"**{inline(term)}**"
    return f"- {head}" + (f": {inline(text)}" if text else "")


# -- the page -----------------------------------------------------------------------------


def document_core_class(name, cls, node):
    out = [f"### `{name}`", ""]
    functions = [f for f in node.body if isinstance(f, ast.FunctionDef)]
    new = next((f for f in functions if f.name == "__new__"), None)
    kind = "exception" if issubclass(cls, BaseException) else "class"
    bases = [ast.unparse(b) for b in node.bases]
    if new is not None:
        out += ["```python", f"{kind} {stub_signature(name, new, owner=name)}", "```", ""]
    elif bases:
        out += ["```python", f"{kind} {name}({', '.join(bases)})", "```", ""]
    out.append(markdown(cls.__doc__ or ""))
    listed = listed_attributes(cls)
    for member in members(cls, node):
        if member in listed and not own_doc(cls, member):
            continue  # in the class docstring's Attributes
        function = next(f for f in node.body if isinstance(f, ast.FunctionDef) and f.name == member)
        attribute = getattr(cls, member)
        if is_property(function):
            returns = ast.unparse(function.returns)
            heading = f"`{name}.{member}` (property: `{returns}`)"
        else:
            heading = f"`{name}.{member}`"
        out += [f"#### {heading}", ""]
        if not is_property(function):
            out += ["```python", stub_signature(f"{name}.{member}", function, owner=name), "```"]
            out.append("")
        out.append(markdown(attribute.__doc__ or ""))
    return out


def document_function(qualified, obj, stub_node):
    if stub_node is not None:
        signature = stub_signature(qualified, stub_node)
    else:
        # Annotations are strings (`from __future__ import annotations`): unquote them.
        text = str(inspect.signature(obj))
        text = re.sub(r": '([^']*)'", r": \1", text)
        text = re.sub(r"-> '([^']*)'$", r"-> \1", text)
        signature = f"{qualified}{text}"
    return [f"### `{qualified}`", "", "```python", signature, "```", "", markdown(obj.__doc__)]


def document_constant(qualified, value, stub_node, note):
    if stub_node is not None and isinstance(stub_node, ast.AnnAssign):
        kind = ast.unparse(stub_node.annotation)
    else:
        kind = type(value).__name__
    return [
        f"### `{qualified}`",
        "",
        "```python",
        f"{qualified}: {kind} = {value!r}",
        "```",
        "",
        f"{inline(note)}\n",
    ]


def page():
    nodes, notes = stub_entries()
    out = [HEADER]
    out.append("## Contents\n")
    for module in MODULES:
        names = ", ".join(f"[`{n}`](#{anchor(module, n)})" for n in public_names(module))
        out.append(f"- `{module.__name__}`: {names}")
    out.append("")
    for module in MODULES:
        out += [f"## `{module.__name__}`", "", markdown(module.__doc__)]
        for name in public_names(module):
            obj = getattr(module, name)
            qualified = name if module is penedge else f"{module.__name__}.{name}"
            from_core = getattr(obj, "__module__", None) in ("penedge", "penedge._core")
            stub_node = nodes.get(name) if module is penedge else None
            if inspect.isclass(obj) and stub_node is not None and from_core:
                out += document_core_class(name, obj, stub_node)
            elif callable(obj) and not inspect.isclass(obj):
                stub_function = stub_node if isinstance(stub_node, ast.FunctionDef) else None
                out += document_function(qualified, obj, stub_function)
            else:
                note = notes.get(name) if module is penedge else None
                note = note or source_comment(module, name) or ""
                out += document_constant(qualified, obj, stub_node, note)
    out += [
        "## Types in the signatures",
        "",
        "The signatures above come from the type stubs (`penedge/_core.pyi`), where these",
        "names are defined:",
        "",
        "```python",
        *type_aliases(),
        "```",
    ]
    text = "\n".join(out)
    text = re.sub(r"\n{3,}", "\n\n", text)
    return text.rstrip() + "\n"


def private(name):
    return name.startswith("_") and not name.startswith("__")


def type_aliases():
    """The private types of the stubs that signatures use (``_Path``, ``_Statistics``, ...),
    as Python text."""
    out = []
    for node in stub_tree().body:
        if isinstance(node, ast.Assign):
            name = node.targets[0].id
        elif isinstance(node, ast.ClassDef):
            name = node.name
        else:
            continue
        if private(name):
            out.append(ast.unparse(node))
    return out


def anchor(module, name):
    """The GitHub anchor of a name's heading."""
    qualified = name if module is penedge else f"{module.__name__}.{name}"
    return re.sub(r"[^a-z0-9_ -]", "", qualified.lower()).replace(" ", "-")


def main(argv=None):
    parser = argparse.ArgumentParser(description="Write docs/api.md from the docstrings.")
    parser.add_argument("--check", action="store_true", help="only check it is up to date")
    args = parser.parse_args(argv)
    missing = undocumented()
    if missing:
        print("no docstring: " + ", ".join(missing), file=sys.stderr)
        return 1
    text = page()
    if args.check:
        if OUTPUT.read_text(encoding="utf-8") != text:
            print(f"{OUTPUT} is out of date: run python3 tools/api_reference.py", file=sys.stderr)
            return 1
        return 0
    OUTPUT.write_text(text, encoding="utf-8")
    print(f"wrote {OUTPUT}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
