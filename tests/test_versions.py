"""The OpenMM versions the package supports: every place that declares them agrees, and importing
rigidlangevin into another OpenMM fails with an ImportError naming both versions."""
import pathlib
import re
import subprocess
import sys

import rigidlangevin

ROOT = pathlib.Path(__file__).resolve().parent.parent
SERIES = rigidlangevin._OPENMM_SERIES


def test_every_declaration_names_the_same_openmm_series():
    major, minor = SERIES.split('.')
    below = f'{major}.{int(minor)+1}'
    declared = {
        'pyproject.toml': re.search(r'"openmm([<>=~][^"]*)"', (ROOT/'pyproject.toml').read_text(encoding='utf-8')).group(1),
        'recipe/meta.yaml': re.search(r'^\s*- openmm (\S+)', (ROOT/'recipe'/'meta.yaml').read_text(encoding='utf-8'), re.M).group(1),
        'CMakeLists.txt': re.search(r'set\(RIGIDLANGEVIN_OPENMM_SERIES (\S+)\)', (ROOT/'CMakeLists.txt').read_text(encoding='utf-8')).group(1),
    }
    assert declared == {'pyproject.toml': f'>={SERIES},<{below}', 'recipe/meta.yaml': f'>={SERIES},<{below}', 'CMakeLists.txt': SERIES}
    pinned = re.search(r'^openmm==(\S+)', (ROOT/'requirements.txt').read_text(encoding='utf-8'), re.M).group(1)
    assert pinned.split('.')[:2] == [major, minor], f'requirements.txt pins openmm {pinned}, outside {SERIES}'


def test_import_refuses_another_openmm_naming_both_versions():
    # OpenMM's version as another release would report it, set before rigidlangevin is imported.
    code = 'import openmm.version; openmm.version.short_version = "8.5.2"; import rigidlangevin'
    result = subprocess.run([sys.executable, '-c', code], capture_output=True, encoding='utf-8')
    assert result.returncode != 0
    last = result.stderr.strip().splitlines()[-1]
    assert last.startswith('ImportError:'), result.stderr
    assert f'needs OpenMM {SERIES}.x' in last and 'has OpenMM 8.5.2' in last, last
    # The same code with the installed version imports.
    same = subprocess.run([sys.executable, '-c', code.replace('"8.5.2"', 'openmm.version.short_version')], capture_output=True, encoding='utf-8')
    assert same.returncode == 0, same.stderr
