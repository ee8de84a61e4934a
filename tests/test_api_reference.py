"""The Python module carries the headers' documentation, and docs/api.md is generated from it."""
import inspect
import pathlib
import subprocess
import sys

import rigidlangevin as rl
import rigidlangevin.hydrodynamics as hydro

ROOT = pathlib.Path(__file__).resolve().parents[1]


def test_api_reference_and_docstrings_are_current():
    # docs/api.md and python/docstrings.i are what scripts/api_reference.py makes of the headers and
    # the package now: a header comment changed without regenerating them fails.
    result = subprocess.run([sys.executable, str(ROOT/'scripts'/'api_reference.py'), '--check'], capture_output=True, encoding='utf-8', timeout=300)
    assert result.returncode == 0, result.stdout+result.stderr


def test_every_public_method_has_its_header_documentation():
    # help() on the wrapped classes shows the header's text, units included; every public method
    # of them, and every public function of rigidlangevin.hydrodynamics, has documentation.
    text = lambda value: ' '.join((value.__doc__ or '').split())
    assert 'A particle may belong to at most one body' in text(rl.RigidLangevinIntegrator.addRigidBody)
    assert 'amu/(nm*ps)' in text(rl.RigidBodyIntegrator) and 'removeCMMotion=False' in text(rl.RigidBodyIntegrator)
    assert all('RigidBodyIntegrator' in text(c) for c in (rl.RigidLangevinIntegrator, rl.RigidBrownianIntegrator))
    assert 'nm^3 (Xrr)' in text(rl.ResistanceTensor)
    assert '(nm)' in text(hydro.sphere) and 'Quantities' in text(hydro.sphere)
    for cls in (rl.RigidBodyIntegrator, rl.RigidLangevinIntegrator, rl.RigidBrownianIntegrator, rl.StickyDipoleForce, rl.ResistanceTensor):
        for name, member in vars(cls).items():
            if name.startswith('_') or not callable(member) or name in ('thisown',):
                continue
            doc = inspect.getdoc(getattr(cls, name)) or ''
            assert len(doc) > 20, f'{cls.__name__}.{name} has no documentation'
    for name in hydro.__all__:
        value = getattr(hydro, name)
        if callable(value):
            assert len(inspect.getdoc(value) or '') > 20, f'hydrodynamics.{name} has no documentation'
