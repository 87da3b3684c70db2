#pragma once
// The one place that knows which Embree major version the renderer is built against (3 on Debian 12,
// 4 on Debian 13 and in Blender 4.2+). The two APIs trace the same scenes; they differ in the header,
// in how a query carries its filter callback (Embree 3: a field of RTCIntersectContext, enabled per
// scene by RTC_SCENE_FLAG_CONTEXT_FILTER_FUNCTION; Embree 4: RTCIntersectArguments /
// RTCOccludedArguments, enabled by RTC_SCENE_FLAG_FILTER_FUNCTION_IN_ARGUMENTS and invoked for every
// geometry with RTC_RAY_QUERY_FLAG_INVOKE_ARGUMENT_FILTER) and in the context type the callback
// receives (RTCIntersectContext / RTCRayQueryContext). Everything else the renderer calls is common.
//
// Every Embree function is called through api(): pointers looked up in the libraries this core
// itself loaded, never in the process's global scope. A Blender that links another Embree (official
// 4.2+ builds and Debian 13's load libembree4.so.4 at start-up, whose C functions have the same names
// as Embree 3's) exports its functions globally, and a plain call would bind to them: the wrong
// version, and not the copy bundled with the package (scripts/native_bundle.py).
#if HAIRLOD_EMBREE_MAJOR >= 4
#include <embree4/rtcore.h>
#else
#include <embree3/rtcore.h>
#endif

namespace hairlod::render::embree {

// The Embree functions the renderer calls, named as Embree names them.
struct Api {
    decltype(&::rtcNewDevice) rtcNewDevice;
    decltype(&::rtcGetDeviceError) rtcGetDeviceError;
    decltype(&::rtcSetDeviceErrorFunction) rtcSetDeviceErrorFunction;
    decltype(&::rtcReleaseDevice) rtcReleaseDevice;
    decltype(&::rtcNewScene) rtcNewScene;
    decltype(&::rtcSetSceneFlags) rtcSetSceneFlags;
    decltype(&::rtcSetSceneBuildQuality) rtcSetSceneBuildQuality;
    decltype(&::rtcCommitScene) rtcCommitScene;
    decltype(&::rtcReleaseScene) rtcReleaseScene;
    decltype(&::rtcNewGeometry) rtcNewGeometry;
    decltype(&::rtcSetSharedGeometryBuffer) rtcSetSharedGeometryBuffer;
    decltype(&::rtcCommitGeometry) rtcCommitGeometry;
    decltype(&::rtcAttachGeometry) rtcAttachGeometry;
    decltype(&::rtcReleaseGeometry) rtcReleaseGeometry;
    decltype(&::rtcIntersect1) rtcIntersect1;
    decltype(&::rtcOccluded1) rtcOccluded1;
};

// The functions of the Embree this core was linked with (looked up once); throws hairlod::Error
// naming a function that cannot be found.
const Api& api();

#if HAIRLOD_EMBREE_MAJOR >= 4

// The per-query context: a caller's own state struct holds it as its first member, and the filter
// callback gets its address back (args->context).
using QueryContext = RTCRayQueryContext;
// The scene flag that lets a query bring its own filter callback.
constexpr RTCSceneFlags kQueryFilterFlag = RTC_SCENE_FLAG_FILTER_FUNCTION_IN_ARGUMENTS;

inline void init_context(QueryContext& context) { rtcInitRayQueryContext(&context); }

// Closest hit, with `filter` called for every candidate hit of every geometry.
inline void intersect1(RTCScene scene, QueryContext& context, RTCFilterFunctionN filter, RTCRayHit& ray_hit) {
    RTCIntersectArguments args;
    rtcInitIntersectArguments(&args);
    args.flags = static_cast<RTCRayQueryFlags>(args.flags | RTC_RAY_QUERY_FLAG_INVOKE_ARGUMENT_FILTER);
    args.context = &context;
    args.filter = filter;
    api().rtcIntersect1(scene, &ray_hit, &args);
}

// Any hit (ray.tfar becomes -inf when one is accepted), with `filter` as above.
inline void occluded1(RTCScene scene, QueryContext& context, RTCFilterFunctionN filter, RTCRay& ray) {
    RTCOccludedArguments args;
    rtcInitOccludedArguments(&args);
    args.flags = static_cast<RTCRayQueryFlags>(args.flags | RTC_RAY_QUERY_FLAG_INVOKE_ARGUMENT_FILTER);
    args.context = &context;
    args.filter = filter;
    api().rtcOccluded1(scene, &ray, &args);
}

#else

using QueryContext = RTCIntersectContext;
constexpr RTCSceneFlags kQueryFilterFlag = RTC_SCENE_FLAG_CONTEXT_FILTER_FUNCTION;

inline void init_context(QueryContext& context) { rtcInitIntersectContext(&context); }

inline void intersect1(RTCScene scene, QueryContext& context, RTCFilterFunctionN filter, RTCRayHit& ray_hit) {
    context.filter = filter;
    api().rtcIntersect1(scene, &context, &ray_hit);
}

inline void occluded1(RTCScene scene, QueryContext& context, RTCFilterFunctionN filter, RTCRay& ray) {
    context.filter = filter;
    api().rtcOccluded1(scene, &context, &ray);
}

#endif

}  // namespace hairlod::render::embree
