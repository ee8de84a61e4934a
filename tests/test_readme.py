"""The README's and the docs' Python snippets run as written, and print what the page says they print
(the line `prints `...`` after a snippet); the README's C++ program builds against the installed
plugin, runs, and prints what the README says."""
import pathlib
import re
import subprocess
import sys

import pytest

ROOT = pathlib.Path(__file__).resolve().parents[1]
README = ROOT/'README.md'
PAGES = [README, *sorted((ROOT/'docs').glob('*.md'))]
SNIPPETS = [(page, code, printed) for page in PAGES
            for code, printed in re.findall(r'```python\n(.*?)```\n(?:\nprints `([^`]*)`)?', page.read_text(encoding='utf-8'), re.S)]


def test_there_are_snippets():
    assert sum(page == README for page, _, _ in SNIPPETS) >= 1 and len(SNIPPETS) >= 3


@pytest.mark.parametrize('page, code, printed', SNIPPETS, ids=[f'{page.stem}-{i}' for i, (page, _, _) in enumerate(SNIPPETS)])
def test_snippet_runs_and_prints_what_it_says(page, code, printed, tmp_path):
    result = subprocess.run([sys.executable, '-c', code], capture_output=True, encoding='utf-8', timeout=600, cwd=tmp_path)
    assert result.returncode == 0, result.stderr[-3000:]
    if printed:
        assert result.stdout.strip().splitlines()[-1] == printed, result.stdout


def test_readme_cpp_program_builds_runs_and_prints_what_it_says(tmp_path):
    # The README's C++ block is a whole program (the kernel registration included), the very file
    # ctest and the pip-install test build too; here it is built as the README says, with the flags
    # `python -m rigidlangevin` prints for the environment the plugin is installed in.
    text = README.read_text(encoding='utf-8')
    program = re.search(r'```cpp\n(.*?)```', text, re.S).group(1)
    printed = re.search(r'```cpp\n.*?```.*?\nprints `([^`]*)`', text, re.S).group(1)
    assert program == (ROOT/'examples'/'cpp'/'QuickStart.cpp').read_text(encoding='utf-8')
    (tmp_path/'QuickStart.cpp').write_text(program, encoding='utf-8')
    flags = subprocess.run([sys.executable, '-m', 'rigidlangevin', '--cflags', '--libs'], capture_output=True, encoding='utf-8', check=True).stdout.split()
    build = subprocess.run(['g++', 'QuickStart.cpp', *flags, '-o', 'quickstart'], capture_output=True, encoding='utf-8', cwd=tmp_path, timeout=600)
    assert build.returncode == 0, build.stderr[-3000:]
    result = subprocess.run([str(tmp_path/'quickstart')], capture_output=True, encoding='utf-8', cwd=tmp_path, timeout=600)
    assert result.returncode == 0 and result.stdout.strip() == printed, result.stdout+result.stderr
