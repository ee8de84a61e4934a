"""Tables and plots of the speed-against-error study."""
import csv

import numpy as np

DYNAMICAL = ['D translational (nm^2/ps)', 'orientational time (ps)', 'VACF']
CONFIGURATIONAL = ['T translational (K)', 'T rotational (K)', 'potential per molecule (kJ/mol)', 'T configurational (K)', 'O-O RDF']


def write(out, rows, stability):
    out.mkdir(parents=True, exist_ok=True)
    fields = []
    for r in rows:
        fields += [k for k in r if k not in fields]
    with open(out/'results.csv', 'w', newline='') as f:
        writer = csv.DictWriter(f, fieldnames=fields)
        writer.writeheader()
        writer.writerows(rows)
    if stability:
        with open(out/'stability.csv', 'w', newline='') as f:
            writer = csv.DictWriter(f, fieldnames=list(stability[0]))
            writer.writeheader()
            writer.writerows(stability)
    table = markdown(rows, stability)
    (out/'table.md').write_text(table)
    print(table)
    plot(out, rows)


def markdown(rows, stability):
    observables = [o for o in DYNAMICAL+CONFIGURATIONAL if any('error '+o in r for r in rows)]
    lines = ['| scene | viscosity (P) | integrator | step (fs) | ns/day | '+' | '.join('error '+o for o in observables)+' |',
             '|'+'---|'*(5+len(observables))]
    for r in rows:
        if r['status'] != 'ok':
            cells = [r['status']]+['']*(len(observables))
        else:
            cells = [f"{r.get('ns/day', float('nan')):.1f}"]+[f"{r['error '+o]:.2%}" if 'error '+o in r and o not in ('VACF', 'O-O RDF')
                                                               else (f"{r['error '+o]:.4f}" if 'error '+o in r else '') for o in observables]
        lines.append(f"| {r['scene']} | {r['viscosity (P)']} | {r['integrator']} | {r['step (fs)']} | "+' | '.join(cells)+' |')
    if stability:
        lines += ['', '| viscosity (P) | integrator | largest stable step (fs) |', '|---|---|---|']
        for s in stability:
            lines.append(f"| {s['viscosity (P)']} | {s['integrator']} | {s['largest stable step (fs)']} |")
    return '\n'.join(lines)+'\n'


def plot(out, rows):
    import matplotlib
    matplotlib.use('Agg')
    import matplotlib.pyplot as plt
    groups = sorted({(r['scene'], r['viscosity (P)']) for r in rows if 'reference' not in r['scene']})
    for scene, viscosity in groups:
        selected = [r for r in rows if r['scene'] == scene and r['viscosity (P)'] == viscosity and r['status'] == 'ok']
        observables = [o for o in DYNAMICAL+CONFIGURATIONAL if any('error '+o in r for r in selected)]
        if not observables:
            continue
        columns = 4
        lines = (len(observables)+columns-1)//columns
        fig, axes = plt.subplots(lines, columns, figsize=(4*columns, 3.2*lines), squeeze=False)
        for ax, observable in zip(axes.flat, observables):
            for integrator in sorted({r['integrator'] for r in selected}):
                points = sorted((r['ns/day'], r['error '+observable]) for r in selected if r['integrator'] == integrator and 'error '+observable in r)
                if points:
                    ax.plot([p[0] for p in points], [max(p[1], 1e-5) for p in points], 'o-', label=integrator)
            ax.set_xscale('log')
            ax.set_yscale('log')
            ax.set_xlabel('ns/day')
            ax.set_ylabel('error')
            ax.set_title(observable, fontsize=9)
        for ax in list(axes.flat)[len(observables):]:
            ax.axis('off')
        axes.flat[0].legend(fontsize=7)
        fig.suptitle(f'{scene}, {viscosity} P: error against speed (step sizes along each line)')
        fig.tight_layout()
        name = scene.split()[0].lower()
        fig.savefig(out/f'error_vs_speed_{name}_{viscosity}P.png', dpi=100)
        plt.close(fig)
