"""Text files and pipes are read and written as UTF-8 whatever the locale.

The docs, tables and reports carry ±, × and units; CI once ran under an ASCII locale, where every
read of a doc page failed. Python picks the locale's encoding unless told, so every text-mode
open, read_text, write_text and subprocess pipe names its encoding, and every script that prints
tables sets its standard output to UTF-8.
"""
import ast
import pathlib
import pytest

ROOT = pathlib.Path(__file__).resolve().parents[1]
SOURCES = sorted(p for folder in ('examples', 'benchmarks', 'python', 'scripts', 'tests')
                 for p in (ROOT/folder).rglob('*.py'))
TEXT_CALLS = {'open', 'read_text', 'write_text'}


def called_name(call):
    return call.func.id if isinstance(call.func, ast.Name) else getattr(call.func, 'attr', None)


def is_binary(call):
    modes = [a for a in call.args[1:2] if isinstance(a, ast.Constant)] + \
            [k.value for k in call.keywords if k.arg == 'mode' and isinstance(k.value, ast.Constant)]
    return any('b' in str(m.value) for m in modes)


def unencoded_calls(tree):
    """Calls that would take the locale's encoding: builtin open, Path.read_text/write_text, text=True pipes."""
    for node in ast.walk(tree):
        if not isinstance(node, ast.Call) or any(k.arg == 'encoding' for k in node.keywords):
            continue
        name = called_name(node)
        builtin_open = name == 'open' and isinstance(node.func, ast.Name)
        if (builtin_open or name in TEXT_CALLS - {'open'}) and not is_binary(node):
            yield node.lineno
        elif any(k.arg in ('text', 'universal_newlines') for k in node.keywords):
            yield node.lineno


@pytest.mark.parametrize('path', SOURCES, ids=[str(p.relative_to(ROOT)) for p in SOURCES])
def test_text_io_names_its_encoding(path):
    source = path.read_text(encoding='utf-8')
    lines = list(unencoded_calls(ast.parse(source)))
    assert not lines, f'{path.name}: text I/O without encoding="utf-8" at lines {lines}'
    prints_non_ascii = 'print(' in source and not source.isascii()
    if "__name__ == '__main__'" in source and path.parts[-3] != 'tests' and prints_non_ascii:
        assert 'sys.stdout.reconfigure(encoding=' in source, f'{path.name} prints but keeps the locale encoding'


def test_the_check_finds_an_unencoded_read():
    tree = ast.parse("open('a.md')\nopen('b', 'rb')\np.read_text()\nsubprocess.run(c, text=True)\nopen('c', encoding='utf-8')")
    assert list(unencoded_calls(tree)) == [1, 3, 4]
