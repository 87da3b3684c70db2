#include "hairlod/render/embree.h"

#include <dlfcn.h>

#include <cstring>
#include <string>

#include "hairlod/core/error.h"

namespace hairlod::render::embree {
namespace {

// Marks this object (the Python extension, or a test executable) for dladdr.
const char kAnchor = 0;

// A handle whose lookups search this object and the libraries it loaded, in load order, and not the
// global scope (dlsym on a library's handle); the global handle where this object is the executable
// itself, whose own libraries are the global scope.
void* own_libraries() {
    Dl_info info{};
    if (dladdr(&kAnchor, &info) != 0 && info.dli_fname != nullptr) {
        if (void* handle = dlopen(info.dli_fname, RTLD_LAZY | RTLD_NOLOAD)) return handle;
    }
    return RTLD_DEFAULT;
}

template <typename Function>
void look_up(void* libraries, const char* name, Function& function) {
    void* address = dlsym(libraries, name);
    if (address == nullptr) {
        const char* why = dlerror();
        throw Error(std::string("Embree: ") + name + " not found in the libraries hairlod loaded" +
                    (why ? std::string(" (") + why + ")" : std::string()));
    }
    static_assert(sizeof(function) == sizeof(address));
    std::memcpy(&function, &address, sizeof(function));  // object to function pointer, as POSIX allows
}

Api load() {
    void* libraries = own_libraries();
    Api api{};
#define HAIRLOD_EMBREE_LOOK_UP(name) look_up(libraries, #name, api.name)
    HAIRLOD_EMBREE_LOOK_UP(rtcNewDevice);
    HAIRLOD_EMBREE_LOOK_UP(rtcGetDeviceError);
    HAIRLOD_EMBREE_LOOK_UP(rtcSetDeviceErrorFunction);
    HAIRLOD_EMBREE_LOOK_UP(rtcReleaseDevice);
    HAIRLOD_EMBREE_LOOK_UP(rtcNewScene);
    HAIRLOD_EMBREE_LOOK_UP(rtcSetSceneFlags);
    HAIRLOD_EMBREE_LOOK_UP(rtcSetSceneBuildQuality);
    HAIRLOD_EMBREE_LOOK_UP(rtcCommitScene);
    HAIRLOD_EMBREE_LOOK_UP(rtcReleaseScene);
    HAIRLOD_EMBREE_LOOK_UP(rtcNewGeometry);
    HAIRLOD_EMBREE_LOOK_UP(rtcSetSharedGeometryBuffer);
    HAIRLOD_EMBREE_LOOK_UP(rtcCommitGeometry);
    HAIRLOD_EMBREE_LOOK_UP(rtcAttachGeometry);
    HAIRLOD_EMBREE_LOOK_UP(rtcReleaseGeometry);
    HAIRLOD_EMBREE_LOOK_UP(rtcIntersect1);
    HAIRLOD_EMBREE_LOOK_UP(rtcOccluded1);
#undef HAIRLOD_EMBREE_LOOK_UP
    return api;
}

}  // namespace

const Api& api() {
    static const Api functions = load();  // thread-safe once (C++11 statics)
    return functions;
}

}  // namespace hairlod::render::embree
