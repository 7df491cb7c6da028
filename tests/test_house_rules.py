"""Rules of the source tree that a reader relies on (docs/architecture.md).

* Imports point one way: ``tir_common`` imports none of the project's packages;
  ``friction_model`` knows no images (imports neither ``tir_contact`` nor ``synthetic``);
  ``synthetic`` may use ``friction_model`` but not ``tir_contact``; ``tir_contact`` uses
  ``synthetic`` only in the two commands that make footage (``demo``, ``synth``).
* No package imports a private module (``_name``) of another package.
* Core dependencies (numpy, scipy, pandas, OpenCV, tifffile, tqdm) are imported
  at module level; only matplotlib may be imported inside a function (it costs about 0.3 s at
  start-up and only plots need it).
* No function has more than 80 code lines (docstring, comments and blank lines not counted)
  unless its docstring says why under a line starting ``Long because``.
"""

from __future__ import annotations

import ast
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
FOOTAGE_COMMANDS = {"tir_contact/commands/demo.py", "tir_contact/commands/synth.py"}
CORE = {"numpy", "scipy", "pandas", "cv2", "tifffile", "tqdm"}
MAX_CODE_LINES = 80


def _sources() -> list[Path]:
    return sorted(p for pkg in PACKAGES for p in (ROOT / pkg).rglob("*.py"))


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
        for node, name in _imports(ast.parse(path.read_text(encoding="utf-8"))):
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
        tree = ast.parse(path.read_text(encoding="utf-8"))
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
        for fn in ast.walk(ast.parse(source)):
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
