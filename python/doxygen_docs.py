"""The public C++ headers' documentation, read with Doxygen, for the Python module and docs/api.md.

    python python/doxygen_docs.py            # rewrite python/docstrings.i from the headers

python/docstrings.i gives every class and method the Python module wraps the docstring its header
writes (SWIG's %feature("docstring")), so that help(rigidlangevin.RigidLangevinIntegrator) says what
the C++ reference says; scripts/api_reference.py writes docs/api.md from the same reading. Both
files are generated, never edited: tests/test_api_reference.py checks that they match the headers.
Needs doxygen (scripts/setup.sh installs it).
"""
import pathlib
import subprocess
import tempfile
import textwrap
import xml.etree.ElementTree as ElementTree

ROOT = pathlib.Path(__file__).resolve().parents[1]
HEADERS = [ROOT/'openmmapi/include/RigidBodyIntegrator.h', ROOT/'openmmapi/include/RigidLangevinIntegrator.h', ROOT/'openmmapi/include/RigidBrownianIntegrator.h', ROOT/'openmmapi/include/StickyDipoleForce.h',
           ROOT/'hydrodynamics/include/ResistanceTensor.h', ROOT/'hydrodynamics/include/CoupledResistance.h']
NAMESPACE = 'RigidLangevinPlugin'
DOCSTRINGS = ROOT/'python/docstrings.i'
# What the Python module adds to a class's C++ description.
PYTHON_NOTES = {
    'RigidBodyIntegrator': 'In Python, temperatures, viscosities, times and lengths may be openmm.unit Quantities (a viscosity '
                           'in any unit, rigidlangevin.poise and centipoise among them); values come back as Quantities. '
                           'setBodyResistance() takes the tensor as a 6x6 array; getBodyResistance() returns (6x6 array, origin, '
                           'reference positions) or None; setBodyBlobs() takes centres and radii as arrays or Quantities, getBodyBlobs() returns '
                           '(centres, radii, reference positions) as Quantities in nm, or None; getWall() returns the height as a Quantity, or None.',
    'RigidLangevinIntegrator': 'In Python, cast() turns an openmm.Integrator that is one (from XmlSerializer) into a RigidLangevinIntegrator.',
    'RigidBrownianIntegrator': 'In Python, cast() turns an openmm.Integrator that is one (from XmlSerializer) into a RigidBrownianIntegrator.',
    'StickyDipoleForce': 'In Python, a site\'s parameters are keyword arguments (Quantities or MD units: nm, kJ/mol, e*nm) starting '
                         'from a named model\'s: addSite(particle, reference1, reference2, model=\'SSD/RF\', dipole=...). '
                         'System.getForce() returns a plain openmm.Force: StickyDipoleForce.cast(force) gives the StickyDipoleForce.',
    'CoupledResistance': 'In Python, getResistance() and getMobility() return (6N, 6N) numpy arrays; '
                         'rigidlangevin.hydrodynamics.coupledResistance(bodies) and coupledMobility(bodies) take the bodies as '
                         '(blob positions, radii, reference point) with numpy arrays and Quantities.',
    'ResistanceTensor': 'In Python, lengths may be Quantities; getMatrix() and getDiffusionTensor() return 6x6 numpy arrays. The module '
                        'rigidlangevin.hydrodynamics offers the same models as functions that take numpy arrays and Quantities.',
}


def run_doxygen(folder):
    """Doxygen's XML for the public headers, in folder/xml."""
    config = '\n'.join([f'INPUT = {" ".join(str(h) for h in HEADERS)}', f'OUTPUT_DIRECTORY = {folder}', 'GENERATE_XML = YES',
                        'GENERATE_HTML = NO', 'GENERATE_LATEX = NO', 'QUIET = YES', 'WARNINGS = NO', 'EXTRACT_ALL = NO',
                        'ENABLE_PREPROCESSING = YES', 'MACRO_EXPANSION = YES',
                        'PREDEFINED = OPENMM_EXPORT_RIGIDLANGEVIN= OPENMM_EXPORT_HYDRODYNAMICS=', 'XML_PROGRAMLISTING = NO'])
    subprocess.run(['doxygen', '-'], input=config, encoding='utf-8', check=True, capture_output=True)
    return pathlib.Path(folder)/'xml'


# Doxygen's XML writes these characters as empty elements.
SYMBOLS = {'ndash': '-', 'mdash': '--', 'nonbreakablespace': ' ', 'linebreak': ' '}


def _text(element):
    """The plain text of a Doxygen description element: paragraphs separated by blank lines, lists
    as '- ' items and preformatted blocks indented, each where it stands; parameter lists and
    return values left out (they are read separately)."""
    if element is None:
        return ''
    blocks = []
    for para in element.findall('para'):
        segments = [[]]  # runs of text, separated by blocks

        def block(text):
            blocks.append(' '.join(''.join(segments[-1]).split()))
            blocks.append(text)
            segments.append([])

        def walk(node, top=False):
            if node.tag in SYMBOLS:
                segments[-1].append(SYMBOLS[node.tag])
            elif node.tag in ('parameterlist', 'simplesect'):
                pass
            elif node.tag in ('itemizedlist', 'orderedlist'):
                block('\n'.join('- '+' '.join(''.join(item.itertext()).split()) for item in node.findall('listitem')))
            elif node.tag in ('preformatted', 'programlisting', 'verbatim'):
                block(textwrap.indent(textwrap.dedent(''.join(node.itertext()).strip('\n')), '    '))
            else:
                if node.text:
                    segments[-1].append(node.text)
                for child in node:
                    walk(child)
            if node.tail and not top:
                segments[-1].append(node.tail)
        walk(para, top=True)
        blocks.append(' '.join(''.join(segments[-1]).split()))
    return '\n\n'.join(b for b in blocks if b.strip())


def _parameters(element):
    """[(name, description)] of a member's @param list, and its @return text."""
    params, returns = [], ''
    if element is None:
        return params, returns
    for item in element.iter('parameteritem'):
        names = [n.text or '' for n in item.iter('parametername')]
        params.append((', '.join(names), _text(item.find('parameterdescription'))))
    for section in element.iter('simplesect'):
        if section.get('kind') == 'return':
            returns = _text(section)
    return params, returns


def read_headers():
    """{class name: {'brief', 'detail', 'members': [{'name', 'signature', 'brief', 'detail', 'params', 'returns'}]}}
    of every documented public class and member of the public headers, in header order."""
    classes = {}
    with tempfile.TemporaryDirectory() as folder:
        xml = run_doxygen(folder)
        for path in sorted(xml.glob(f'class{NAMESPACE}_1_1*.xml')):
            compound = ElementTree.parse(path).getroot().find('compounddef')
            name = compound.find('compoundname').text.split('::')[-1]
            members = []
            for section in compound.findall('sectiondef'):
                if not section.get('kind', '').startswith('public'):
                    continue
                for member in section.findall('memberdef'):
                    if member.get('kind') not in ('function', 'enum'):
                        continue
                    params, returns = _parameters(member.find('detaileddescription'))
                    kind = member.find('type')
                    kind = ''.join(kind.itertext()) if kind is not None else ''
                    signature = (kind+' '+member.findtext('name')+(member.findtext('argsstring') or '')).strip()
                    if member.get('kind') == 'enum':
                        signature = 'enum '+member.findtext('name')+' {'+', '.join(v.findtext('name') for v in member.findall('enumvalue'))+'}'
                    members.append({'name': member.findtext('name'), 'kind': member.get('kind'), 'signature': ' '.join(signature.split()),
                                    'brief': _text(member.find('briefdescription')), 'detail': _text(member.find('detaileddescription')),
                                    'params': params, 'returns': returns, 'line': int(member.find('location').get('line'))})
            members.sort(key=lambda m: m['line'])
            classes[name] = {'brief': _text(compound.find('briefdescription')), 'detail': _text(compound.find('detaileddescription')),
                             'header': pathlib.Path(compound.find('location').get('file')).name, 'members': members}
    order = [h.name for h in HEADERS]
    return dict(sorted(classes.items(), key=lambda item: order.index(item[1]['header'])))


def _wrap(text, width=100):
    """Text paragraphs wrapped to width; indented blocks and list items kept as they are."""
    out = []
    for block in text.split('\n\n'):
        if block.startswith((' ', '- ')) or '\n' in block:
            out.append(block)
        else:
            out.append(textwrap.fill(block, width, break_long_words=False, break_on_hyphens=False))
    return '\n\n'.join(out)


def member_docstring(member):
    """A member's documentation as a Python docstring: description, then Parameters and Returns."""
    parts = [_wrap(p) for p in (member['brief'], member['detail']) if p]
    if member['params']:
        parts.append('Parameters\n----------\n'+'\n'.join(f'{name}\n{textwrap.indent(_wrap(text, 96), "    ")}' for name, text in member['params']))
    if member['returns']:
        parts.append('Returns\n-------\n'+_wrap(member['returns']))
    return '\n\n'.join(parts)


def class_docstring(name, cls):
    """The class's description, its constructors' (with their parameters) and the Python notes."""
    parts = [_wrap(p) for p in (cls['brief'], cls['detail']) if p]
    for member in cls['members']:
        if member['kind'] == 'function' and member['name'] == name and (member['brief'] or member['params']):
            parts.append(member['signature']+'\n\n'+member_docstring(member))
    if name in PYTHON_NOTES:
        parts.append(_wrap(PYTHON_NOTES[name]))
    return '\n\n'.join(parts)


def _swig_string(text):
    return '"'+text.replace('\\', '\\\\').replace('"', '\\"').replace('\n', '\\n')+'"'


def docstrings_interface(classes):
    """The text of python/docstrings.i: a %feature("docstring") per class and method (overloads'
    documentation joined, as Python has one method for them)."""
    lines = ['/* Generated by python/doxygen_docs.py from the public headers\' documentation: do not edit. */', '']
    for name, cls in classes.items():
        lines.append(f'%feature("docstring") {NAMESPACE}::{name} {_swig_string(class_docstring(name, cls))};')
        by_name = {}
        for member in cls['members']:
            if member['kind'] == 'function' and member['name'] != name and not member['name'].startswith('~'):
                by_name.setdefault(member['name'], []).append(member)
        for method, overloads in by_name.items():
            texts = []
            for member in overloads:
                text = member_docstring(member)
                if len(overloads) > 1:
                    text = member['signature']+'\n\n'+text
                if text and text not in texts:
                    texts.append(text)
            if texts:
                joined = '\n\n'.join(texts)
                lines.append(f'%feature("docstring") {NAMESPACE}::{name}::{method} {_swig_string(joined)};')
        lines.append('')
    return '\n'.join(lines)


if __name__ == '__main__':
    DOCSTRINGS.write_text(docstrings_interface(read_headers()), encoding='utf-8')
    print(f'wrote {DOCSTRINGS}')
