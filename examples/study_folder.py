"""An appendable study on disk: runs kept one file each, so that a study too long for one sitting is
finished in parts, and refused where parts would not belong together.

A study folder holds one folder per stage (runs/<stage>/), each with stage.json, the stage's
definition (what makes its runs comparable: the model, as a fingerprint of its OpenMM System, and
the settings that change what a run measures) and the inputs it was started with (a box edge, say,
taken from an earlier stage when this one began and kept from then on), and its runs, one .npz
each, numbered in the order they were started; run i is seeded from i, so that a run appended later
is independent of the earlier ones and a folder filled in parts holds the runs one sitting would
have made. Reopening a stage with another definition raises StudyMismatch, naming what differs.
A run under way may keep its progress (stage.progress(index, seed), a hidden file beside the runs)
so that a run cut short (a session's end, a killed job) resumes where it last saved, not from its
start; the progress goes when the run is saved.

    folder = StudyFolder('results/study')
    stage = folder.stage('density', {'model': system_fingerprint(system), 'ps': 1000}, inputs={})
    for index in stage.missing(4):           # the runs still to do for 4 in all
        stage.save(index, volumes=..., seed=...)
    runs = stage.runs()                      # [(index, {name: array}), ...]
"""
import hashlib
import json
import os
import pathlib

import numpy as np


class StudyMismatch(Exception):
    """A stage on disk was made with another model or other settings than asked for now."""


def system_fingerprint(system):
    """SHA-256 of an OpenMM System's XML (particles, forces and their parameters, the default box):
    the model a run used, in a form two runs can compare."""
    import openmm as mm
    return hashlib.sha256(mm.XmlSerializer.serialize(system).encode()).hexdigest()


def _plain(value):
    """value as JSON holds it, so that a definition compares equal to itself read back."""
    return json.loads(json.dumps(value, sort_keys=True))


class RunProgress:
    """What a run under way has saved so far (arrays and numbers of the run's choosing: its
    Context's checkpoint, the series recorded so far), with the seed the run was started with."""

    def __init__(self, path, seed):
        self.path, self.seed = pathlib.Path(path), int(seed)

    def load(self):
        """The arrays last saved, or None if the run has saved none. A file that cannot be read, or
        was saved by a run of another seed, raises StudyMismatch naming it and the fix."""
        if not self.path.exists():
            return None
        try:
            with np.load(self.path) as data:
                saved = {k: data[k] for k in data.files}
        except Exception as error:
            raise StudyMismatch(f'{self.path} (a run\'s saved progress) cannot be read ({error}); remove it to start that run '
                                f'again') from error
        if int(saved.get('progress_seed', -1)) != self.seed:
            raise StudyMismatch(f'{self.path} holds the progress of a run with seed {saved.get("progress_seed")}, not {self.seed}; '
                                f'remove it to start that run again')
        return saved

    def save(self, **arrays):
        """Keep arrays as the run's progress (written whole or not at all)."""
        temporary = self.path.with_name(self.path.stem+'.tmp.npz')
        np.savez_compressed(temporary, progress_seed=self.seed, **arrays)
        os.replace(temporary, self.path)

    def clear(self):
        self.path.unlink(missing_ok=True)


class Stage:
    """One stage's folder: its definition, inputs and runs."""

    def __init__(self, path, name, definition, inputs):
        self.path, self.name = pathlib.Path(path), name
        manifest = self.path/'stage.json'
        definition = _plain(definition)
        if manifest.exists():
            stored = json.loads(manifest.read_text(encoding='utf-8'))
            if stored.get('definition') != definition:
                differ = sorted(k for k in set(definition) | set(stored.get('definition', {}))
                                if definition.get(k) != stored.get('definition', {}).get(k))
                raise StudyMismatch(f'{self.path} holds runs of another {name} stage than this one: it differs in {", ".join(differ)} '
                                    f'(stored {[stored.get("definition", {}).get(k) for k in differ]}, asked '
                                    f'{[definition.get(k) for k in differ]}); its runs cannot be mixed with new ones. Use another '
                                    f'output folder, or remove {self.path} to start this stage again')
            self.inputs = stored.get('inputs', {})
        else:
            if inputs is None:
                raise ValueError(f'stage {name} does not exist yet in {self.path.parent} and has no inputs to start from')
            self.path.mkdir(parents=True, exist_ok=True)
            self.inputs = _plain(inputs)
            temporary = manifest.with_suffix(f'.{os.getpid()}.tmp')  # processes started apart may start a stage together
            temporary.write_text(json.dumps({'name': name, 'definition': definition, 'inputs': self.inputs}, indent=1, sort_keys=True), encoding='utf-8')
            os.replace(temporary, manifest)
        self.definition = definition

    def _file(self, index):
        return self.path/f'run_{index:04d}.npz'

    def indices(self):
        """The indices of the runs on disk, ascending."""
        return sorted(int(p.stem.split('_')[1]) for p in self.path.glob('run_*.npz'))

    def missing(self, total):
        """Indices of the runs still to do for `total` runs in all (the lowest ones not on disk)."""
        have = set(self.indices())
        return [i for i in range(total) if i not in have][:max(0, total-len(have))]

    def next_indices(self, count):
        """`count` new indices after every run on disk (for appending)."""
        have = self.indices()
        first = have[-1]+1 if have else 0
        return list(range(first, first+count))

    def save(self, index, **arrays):
        """Write run `index` (numbers and arrays); written whole or not at all. Its progress goes."""
        temporary = self.path/f'.run_{index:04d}.tmp.npz'
        np.savez_compressed(temporary, **arrays)
        os.replace(temporary, self._file(index))
        self.progress(index, 0).clear()

    def progress(self, index, seed):
        """Run `index`'s progress while it is under way (see RunProgress)."""
        return RunProgress(self.path/f'.progress_{index:04d}.npz', seed)

    def load(self, index):
        with np.load(self._file(index)) as data:
            return {k: data[k] for k in data.files}

    def runs(self):
        """[(index, {name: array})] of every run on disk, by index."""
        return [(i, self.load(i)) for i in self.indices()]


class StudyFolder:
    """The folder of a study: stage(name, definition, inputs) opens or starts runs/<name>/."""

    def __init__(self, root):
        self.root = pathlib.Path(root)

    def has(self, name):
        return (self.root/'runs'/name/'stage.json').exists()

    def stage(self, name, definition, inputs=None):
        """The stage `name`: opened if it exists (its definition must equal `definition`; its own
        inputs are kept), else started with `inputs` (which must then be given)."""
        return Stage(self.root/'runs'/name, name, definition, inputs)
