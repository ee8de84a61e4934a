"""Compiler and linker flags for C++ programs that use the plugin as installed here.

    g++ app.cpp $(python -m rigidlangevin --cflags --libs) -o app     # the integrator, with the Reference kernels
    g++ app.cpp $(python -m rigidlangevin --cflags --libs-hydrodynamics) -o app   # resistance tensors alone
    cmake -DCMAKE_PREFIX_PATH=$(python -m rigidlangevin --prefix) ...  # for find_package(RigidLangevin)

The plugin's libraries and headers are installed beside OpenMM's (in the directory `--prefix`
prints); the flags use absolute paths and set the runtime search path, so they work from anywhere.
"""
import argparse
import os

import openmm.version


def prefix():
    """The directory holding OpenMM's and the plugin's include/ and lib/."""
    return os.path.dirname(os.path.abspath(openmm.version.openmm_library_path))  # openmm_library_path is its lib/


def flags(cflags=False, libs=False, libs_hydrodynamics=False):
    root = prefix()
    lib, plugins = os.path.join(root, 'lib'), os.path.join(root, 'lib', 'plugins')
    out = []
    if cflags:
        out += ['-std=c++17', f'-I{os.path.join(root, "include", "rigidlangevin")}', f'-I{os.path.join(root, "include")}']
    if libs:
        out += [f'-L{lib}', f'-L{plugins}', '-lRigidLangevin', '-lRigidLangevinReference', '-lRigidLangevinHydrodynamics', '-lOpenMM',
                f'-Wl,-rpath,{lib}', f'-Wl,-rpath,{plugins}']
    elif libs_hydrodynamics:
        out += [f'-L{lib}', '-lRigidLangevinHydrodynamics', '-lOpenMM', f'-Wl,-rpath,{lib}']
    return out


def main():
    parser = argparse.ArgumentParser(prog='python -m rigidlangevin', description=__doc__.split('\n')[0])
    parser.add_argument('--cflags', action='store_true', help='the C++ standard and include directories')
    parser.add_argument('--libs', action='store_true', help='link the integrator, the Reference kernels, the hydrodynamics library and OpenMM')
    parser.add_argument('--libs-hydrodynamics', action='store_true', help='link the hydrodynamics library and OpenMM alone')
    parser.add_argument('--prefix', action='store_true', help='the directory holding include/ and lib/ (for CMAKE_PREFIX_PATH)')
    args = parser.parse_args()
    if args.prefix:
        print(prefix())
        return
    if not (args.cflags or args.libs or args.libs_hydrodynamics):
        parser.error('ask for --cflags, --libs, --libs-hydrodynamics or --prefix')
    print(' '.join(flags(args.cflags, args.libs, args.libs_hydrodynamics)))


if __name__ == '__main__':
    main()
