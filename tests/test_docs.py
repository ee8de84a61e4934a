"""The README and the docs pages hold together: every relative link resolves (to a file or folder,
and to a heading or anchor where it names one), and every "value ± error" a study's page quotes is
one its committed results files hold (to the digits quoted), so a page cannot drift from the
results that the study's code writes and its tests check."""
import pathlib
import re

import pytest

ROOT = pathlib.Path(__file__).resolve().parents[1]
PAGES = [ROOT/'README.md', *sorted((ROOT/'docs').glob('*.md'))]
# Each study page and the results files its numbers are read from.
RESULTS = {
    'README.md': ['examples/results/ssd_scene/table.md', 'benchmarks/hydrodynamics/results/brownian_vs_rigid_multiblobs_wall.md'],
    'docs/banana.md': ['examples/results/banana_scene/*.md', 'examples/results/banana_scene/history_medium_3_replicas/*.md',
                       'benchmarks/platforms/results/banana_solvent*.csv'],
    'docs/water.md': ['examples/results/ssd_scene/table.md', 'examples/results/ssd_properties/table.md'],
    'docs/speed-vs-error.md': ['benchmarks/speed_vs_error/results/*.md'],
    'docs/user-guide.md': ['examples/results/sedimented_boomerangs/table.md', 'benchmarks/speed_vs_error/results/colloids.md'],
}
# Quoted numbers with no results file to read them from, and why.
NOT_IN_RESULTS = {
    'docs/banana.md': {('3.54', '0.09'), ('3.23', '0.08'), ('3.28', '0.09'),  # earlier timing runs, not kept
                       ('0.016', '0.006')},  # the viscosity runs before the second n = 1 runs, not kept
    'docs/speed-vs-error.md': {('4.4', '1.4')},  # the three-replica run the 64 replicas replaced
    'docs/user-guide.md': {('15.6', '0.4'), ('6.6', '0.2'),  # examples/protein_diffusion.py prints them; it keeps no results file
                           ('0.155', '0.003')},  # a scratch build without the drift (tests/test_sedimented_boomerangs.py's comment)
}
LINK = re.compile(r'!?\[[^\]]*\]\(([^)\s]+)\)')
PAIR = re.compile(r'([+−-]?\d+(?:\.\d+)?) ?(?:±|\+-) ?(\d+(?:\.\d+)?)')


def prose(path):
    """The page without its fenced code blocks (a # there is a comment, a [..](..) code)."""
    return re.sub(r'```.*?```', '', path.read_text(encoding='utf-8'), flags=re.S)


def anchors(path):
    """GitHub's anchors of a markdown page: each heading lowercased, stripped of punctuation,
    spaces made hyphens (a repeated one numbered), and the page's explicit <a id=...>."""
    text = prose(path)
    found, seen = set(re.findall(r'<a id="([^"]+)"', text)), {}
    for heading in re.findall(r'^#+ (.*)$', text, re.M):
        slug = re.sub(r'[^\w\- ]', '', heading.strip().lower()).replace(' ', '-')
        found.add(slug if slug not in seen else f'{slug}-{seen[slug]}')
        seen[slug] = seen.get(slug, 0)+1
    return found


def broken_links(page):
    broken = []
    for target in LINK.findall(prose(page)):
        if re.match(r'[a-z]+:', target):
            continue  # a web address
        path, _, anchor = target.partition('#')
        resolved = (page.parent/path).resolve() if path else page
        if not resolved.exists():
            broken.append(target)
        elif anchor and resolved.suffix == '.md' and anchor not in anchors(resolved):
            broken.append(target)
    return broken


@pytest.mark.parametrize('page', PAGES, ids=[str(p.relative_to(ROOT)) for p in PAGES])
def test_relative_links_resolve(page):
    assert not broken_links(page), f'{page.name}: links that lead nowhere: {broken_links(page)}'


def test_the_link_check_can_fail(tmp_path):
    # GitHub's anchors (punctuation dropped, a repeated heading numbered, headings in code blocks
    # not headings); a missing file or anchor is broken, a web address is not looked at.
    page = tmp_path/'page.md'
    page.write_text('## From C++\n## With `openmm.app`\n## Notes\n## Notes\n```\n# not a heading\n```\n'
                    '[a](#from-c) [b](#with-openmmapp) [c](#notes-1) [d](#not-a-heading) [e](other.md) '
                    '[f](https://example.org/x#y) [g](page.md#notes) ![h](#from-c)\n', encoding='utf-8')
    assert broken_links(page) == ['#not-a-heading', 'other.md']


def matches(quoted, held):
    """Whether a quoted number is a held one to the quoted digits (rounded, half a last digit)."""
    digits = len(quoted.split('.')[1]) if '.' in quoted else 0
    return abs(float(quoted)-float(held)) <= 0.5*10**-digits*(1+1e-9)


def pairs(text):
    return [(a.replace('−', '-'), b) for a, b in PAIR.findall(text)]


@pytest.mark.parametrize('page', sorted(RESULTS))
def test_quoted_results_are_the_results_files(page):
    held = [pair for pattern in RESULTS[page] for path in sorted(ROOT.glob(pattern)) for pair in pairs(path.read_text(encoding='utf-8'))]
    assert held, f'no results for {page}'
    missing = [(value, error) for value, error in pairs(prose(ROOT/page))
               if (value, error) not in NOT_IN_RESULTS.get(page, set())
               and not any(matches(value, v) and matches(error, e) for v, e in held)]
    assert not missing, f'{page} quotes values ± errors its results files do not hold: {missing}'


def test_the_number_check_can_fail():
    # A value quoted a last digit off, or its error, is not the results files' number; the same
    # rounded is.
    held = pairs('| explicit | 4.159 ± 0.098 (2.4%) | and +0.0267 +- 0.0042 |')
    assert held == [('4.159', '0.098'), ('+0.0267', '0.0042')]
    assert matches('4.16', '4.159') and matches('0.10', '0.098') and matches('0.027', '0.0267')
    assert not matches('4.158', '4.159') and not matches('0.11', '0.098')
