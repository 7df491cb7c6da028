"""Rules of the source tree that a reader relies on (docs/architecture.md).

* Imports point one way: ``tir_common`` imports none of the project's packages;
  ``friction_model`` knows no images (imports neither ``tir_contact`` nor ``synthetic``);
  ``synthetic`` may use ``friction_model`` but not ``tir_contact``; ``tir_contact`` uses
  ``synthetic`` only where it makes data (the library's ``demo`` and the ``synth`` command).
* No package imports a private module (``_name``) of another package.
* Core dependencies (numpy, scipy, pandas, OpenCV, tifffile, tqdm) are imported
  at module level; only matplotlib may be imported inside a function (it costs about 0.3 s at
  start-up and only plots need it).
* No function has more than 80 code lines (docstring, comments and blank lines not counted)
  unless its docstring says why under a line starting ``Long because``.
"""

from __future__ import annotations

import ast
import functools
import io
import tokenize
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
PACKAGES = ("tir_common", "friction_model", "synthetic", "tir_contact")
MAY_IMPORT = {
    "tir_common": set(),
    "friction_model": {"tir_common"},
    "synthetic": {"tir_common", "friction_model"},
    "tir_contact": {"tir_common", "friction_model"},
}
#: The two modules of tir_contact that make data: the library's demo and ``synth``.
FOOTAGE_COMMANDS = {"tir_contact/demo.py", "tir_contact/commands/synth.py"}
CORE = {"numpy", "scipy", "pandas", "cv2", "tifffile", "tqdm"}
MAX_CODE_LINES = 80


def _sources() -> list[Path]:
    return sorted(p for pkg in PACKAGES for p in (ROOT / pkg).rglob("*.py"))


@functools.cache
def _tree(path: Path) -> ast.Module:
    """The parsed source of `path` (parsed once for all the rules here; not modified)."""
    return ast.parse(path.read_text(encoding="utf-8"))


def _imports(tree: ast.AST) -> list[tuple[ast.AST, str]]:
    out = []
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            out += [(node, a.name) for a in node.names]
        elif isinstance(node, ast.ImportFrom) and node.module and node.level == 0:
            out += [(node, node.module)]
            out += [(node, f"{node.module}.{a.name}") for a in node.names]
    return out


def _code_lines(source: str, node: ast.FunctionDef | ast.AsyncFunctionDef) -> int:
    """Lines of ``node`` holding code: no docstring, comment-only or blank lines."""
    lines = source.splitlines()[node.lineno - 1 : node.end_lineno]
    doc = ast.get_docstring(node, clean=False)
    skip: set[int] = set()
    if doc is not None:
        first = node.body[0]
        skip = set(range(first.lineno - node.lineno, first.end_lineno - node.lineno + 1))
    code = set()
    text = "\n".join(lines)
    for tok in tokenize.generate_tokens(io.StringIO(text).readline):
        if tok.type not in (tokenize.COMMENT, tokenize.NL, tokenize.NEWLINE, tokenize.INDENT,
                            tokenize.DEDENT, tokenize.ENDMARKER):
            code.update(range(tok.start[0] - 1, tok.end[0]))
    return len(code - skip)


def test_imports_point_one_way_and_stay_public():
    wrong = []
    for path in _sources():
        rel = path.relative_to(ROOT).as_posix()
        own = rel.split("/")[0]
        for node, name in _imports(_tree(path)):
            top = name.split(".")[0]
            if top not in PACKAGES or top == own:
                continue
            allowed = MAY_IMPORT[own] | ({"synthetic"} if rel in FOOTAGE_COMMANDS else set())
            if top not in allowed:
                wrong.append(f"{rel}:{node.lineno} imports {name} ({own} may not use {top})")
            elif any(part.startswith("_") for part in name.split(".")[1:]):
                wrong.append(f"{rel}:{node.lineno} imports the private {name}")
    assert not wrong, "\n".join(sorted(set(wrong)))


def test_core_dependencies_are_imported_at_module_level():
    local = []
    for path in _sources():
        tree = _tree(path)
        for fn in ast.walk(tree):
            if not isinstance(fn, ast.FunctionDef | ast.AsyncFunctionDef):
                continue
            for node, name in _imports(fn):
                if name.split(".")[0] in CORE:
                    local.append(f"{path.relative_to(ROOT)}:{node.lineno} {name} in {fn.name}")
    assert not local, "\n".join(sorted(set(local)))


def test_no_function_is_long_without_a_reason():
    long = []
    for path in _sources():
        source = path.read_text(encoding="utf-8")
        for fn in ast.walk(_tree(path)):
            if not isinstance(fn, ast.FunctionDef | ast.AsyncFunctionDef):
                continue
            n = _code_lines(source, fn)
            doc = ast.get_docstring(fn) or ""
            if n > MAX_CODE_LINES and "Long because" not in doc:
                long.append(f"{path.relative_to(ROOT)}:{fn.lineno} {fn.name}: {n} code lines")
    assert not long, "\n".join(long)


@pytest.mark.parametrize("name", ["LICENSE", "docs/architecture.md"])
def test_repository_files_exist(name):
    assert (ROOT / name).is_file()


def _module_name(path: Path) -> str:
    parts = list(path.relative_to(ROOT).with_suffix("").parts)
    if parts[-1] == "__init__":
        parts.pop()
    return ".".join(parts)


def _import_graph() -> dict[str, set[str]]:
    """Project module -> project modules it imports anywhere (module level, inside a function,
    under ``TYPE_CHECKING``): ``from a.b import c`` is an edge to ``a.b.c`` when that is a
    module, else to ``a.b``; relative imports are resolved against the importing package."""
    modules = {_module_name(p): p for p in _sources()}
    graph: dict[str, set[str]] = {name: set() for name in modules}
    for name, path in modules.items():
        package = name if path.name == "__init__.py" else name.rpartition(".")[0]
        for node in ast.walk(_tree(path)):
            targets: list[str] = []
            if isinstance(node, ast.Import):
                targets = [a.name for a in node.names]
            elif isinstance(node, ast.ImportFrom):
                base = node.module or ""
                if node.level:
                    anchor = package.split(".")[: len(package.split(".")) - node.level + 1]
                    base = ".".join([*anchor, *([base] if base else [])])
                targets = [f"{base}.{a.name}" if f"{base}.{a.name}" in modules else base
                           for a in node.names]
            graph[name].update(t for t in targets if t in modules and t != name)
    return graph


def _cycle(graph: dict[str, set[str]]) -> list[str] | None:
    """One import circle of ``graph`` (a depth-first search), or None."""
    state: dict[str, int] = {}
    stack: list[str] = []

    def visit(node: str) -> list[str] | None:
        state[node] = 1
        stack.append(node)
        for nxt in sorted(graph[node]):
            if state.get(nxt) == 1:
                return [*stack[stack.index(nxt):], nxt]
            if nxt not in state and (found := visit(nxt)) is not None:
                return found
        stack.pop()
        state[node] = 2
        return None

    for start in sorted(graph):
        if start not in state and (found := visit(start)) is not None:
            return found
    return None


def test_cycle_finder_sees_a_circle():
    assert _cycle({"a": {"b"}, "b": {"c"}, "c": {"a"}}) == ["a", "b", "c", "a"]
    assert _cycle({"a": {"b"}, "b": {"c"}, "c": set()}) is None


def test_no_import_circles():
    """No two modules import each other, directly or round a longer circle, not even through
    a function-local or type-checking import (those only hide a circle)."""
    circle = _cycle(_import_graph())
    assert circle is None, "import circle: " + " -> ".join(circle or [])
