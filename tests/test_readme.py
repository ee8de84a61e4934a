"""The README's Python snippets run as written, and print what the README says they print (the
line `prints `...`` after a snippet)."""
import pathlib
import re
import subprocess
import sys

import pytest

README = pathlib.Path(__file__).resolve().parents[1]/'README.md'
SNIPPETS = re.findall(r'```python\n(.*?)```\n(?:\nprints `([^`]*)`)?', README.read_text(), re.S)


def test_there_are_snippets():
    assert len(SNIPPETS) >= 3


@pytest.mark.parametrize('code, printed', SNIPPETS, ids=[f'snippet{i}' for i in range(len(SNIPPETS))])
def test_readme_snippet_runs_and_prints_what_it_says(code, printed, tmp_path):
    result = subprocess.run([sys.executable, '-c', code], capture_output=True, text=True, timeout=600, cwd=tmp_path)
    assert result.returncode == 0, result.stderr[-3000:]
    if printed:
        assert result.stdout.strip().splitlines()[-1] == printed, result.stdout
