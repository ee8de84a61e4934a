#include "RigidBrownianIntegrator.h"
#include "RigidBrownianIntegratorProxy.h"
#include "RigidLangevinIntegrator.h"
#include "RigidLangevinIntegratorProxy.h"
#include "StickyDipoleForce.h"
#include "StickyDipoleForceProxy.h"
#include "openmm/serialization/SerializationProxy.h"
#include <typeinfo>

using namespace RigidLangevinPlugin;

// Register the proxies as soon as the library is loaded, as OpenMM's own plugins do.
#if defined(WIN32)
    #include <windows.h>
    extern "C" OPENMM_EXPORT_RIGIDLANGEVIN void registerRigidLangevinSerializationProxies();
    BOOL WINAPI DllMain(HANDLE hModule, DWORD ul_reason_for_call, LPVOID lpReserved) {
        if (ul_reason_for_call == DLL_PROCESS_ATTACH)
            registerRigidLangevinSerializationProxies();
        return TRUE;
    }
#else
    extern "C" void __attribute__((constructor)) registerRigidLangevinSerializationProxies();
#endif

extern "C" OPENMM_EXPORT_RIGIDLANGEVIN void registerRigidLangevinSerializationProxies() {
    OpenMM::SerializationProxy::registerProxy(typeid(RigidLangevinIntegrator), new RigidLangevinIntegratorProxy());
    OpenMM::SerializationProxy::registerProxy(typeid(RigidBrownianIntegrator), new RigidBrownianIntegratorProxy());
    OpenMM::SerializationProxy::registerProxy(typeid(StickyDipoleForce), new StickyDipoleForceProxy());
}
