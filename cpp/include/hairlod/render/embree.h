#pragma once
// The one place that knows which Embree major version the renderer is built against (3 on Debian 12,
// 4 on Debian 13 and in Blender 4.2+). The two APIs trace the same scenes; they differ in the header,
// in how a query carries its filter callback (Embree 3: a field of RTCIntersectContext, enabled per
// scene by RTC_SCENE_FLAG_CONTEXT_FILTER_FUNCTION; Embree 4: RTCIntersectArguments /
// RTCOccludedArguments, enabled by RTC_SCENE_FLAG_FILTER_FUNCTION_IN_ARGUMENTS and invoked for every
// geometry with RTC_RAY_QUERY_FLAG_INVOKE_ARGUMENT_FILTER) and in the context type the callback
// receives (RTCIntersectContext / RTCRayQueryContext). Everything else the renderer calls is common.
#if HAIRLOD_EMBREE_MAJOR >= 4
#include <embree4/rtcore.h>
#else
#include <embree3/rtcore.h>
#endif

namespace hairlod::render::embree {

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
    rtcIntersect1(scene, &ray_hit, &args);
}

// Any hit (ray.tfar becomes -inf when one is accepted), with `filter` as above.
inline void occluded1(RTCScene scene, QueryContext& context, RTCFilterFunctionN filter, RTCRay& ray) {
    RTCOccludedArguments args;
    rtcInitOccludedArguments(&args);
    args.flags = static_cast<RTCRayQueryFlags>(args.flags | RTC_RAY_QUERY_FLAG_INVOKE_ARGUMENT_FILTER);
    args.context = &context;
    args.filter = filter;
    rtcOccluded1(scene, &ray, &args);
}

#else

using QueryContext = RTCIntersectContext;
constexpr RTCSceneFlags kQueryFilterFlag = RTC_SCENE_FLAG_CONTEXT_FILTER_FUNCTION;

inline void init_context(QueryContext& context) { rtcInitIntersectContext(&context); }

inline void intersect1(RTCScene scene, QueryContext& context, RTCFilterFunctionN filter, RTCRayHit& ray_hit) {
    context.filter = filter;
    rtcIntersect1(scene, &context, &ray_hit);
}

inline void occluded1(RTCScene scene, QueryContext& context, RTCFilterFunctionN filter, RTCRay& ray) {
    context.filter = filter;
    rtcOccluded1(scene, &context, &ray);
}

#endif

}  // namespace hairlod::render::embree
