#ifndef RIGID_LANGEVIN_HYDRODYNAMICS_WINDOW_EXPORT_H_
#define RIGID_LANGEVIN_HYDRODYNAMICS_WINDOW_EXPORT_H_

// Symbol visibility of the hydrodynamics library, as OpenMM does it for its own libraries.
#if defined(_MSC_VER)
    #if defined(RIGIDLANGEVIN_HYDRODYNAMICS_BUILDING_SHARED_LIBRARY)
        #define OPENMM_EXPORT_HYDRODYNAMICS __declspec(dllexport)
    #else
        #define OPENMM_EXPORT_HYDRODYNAMICS __declspec(dllimport)
    #endif
#else
    #define OPENMM_EXPORT_HYDRODYNAMICS __attribute__((visibility("default")))
#endif

#endif // RIGID_LANGEVIN_HYDRODYNAMICS_WINDOW_EXPORT_H_
