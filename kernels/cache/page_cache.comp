// Vulkan entry points of the page cache's update pass, one module per -DMV_ENTRY_<name> (bodies:
// common/page_cache.h).
#version 460
#extension GL_GOOGLE_include_directive : require
#include "common/mv_glsl_prelude.h"
#include "common/page_cache.h"

#if defined(MV_ENTRY_lru_flags)
layout(push_constant) uniform Args { MvBufU32 usage; MvBufU32 lru; MvBufU32 flags; MvCacheParams p; } args;
void main() { mv_cache_lru_flags(args.usage, args.lru, args.flags, args.p, MV_GLOBAL_ID(), MV_GLOBAL_SIZE()); }
#elif defined(MV_ENTRY_lru_scatter)
layout(push_constant) uniform Args { MvBufU32 lru; MvBufU32 pos; MvBufU32 next; MvCacheParams p; } args;
void main() { mv_cache_lru_scatter(args.lru, args.pos, args.next, args.p, MV_GLOBAL_ID(), MV_GLOBAL_SIZE()); }
#elif defined(MV_ENTRY_request_flags)
layout(push_constant) uniform Args { MvBufU32 request; MvBufU32 table; MvBufU32 flags; MvCacheParams p; } args;
void main() {
  mv_cache_request_flags(args.request, args.table, args.flags, args.p, MV_GLOBAL_ID(), MV_GLOBAL_SIZE());
}
#elif defined(MV_ENTRY_request_compact)
layout(push_constant) uniform Args { MvBufU32 pos; MvBufU32 list; MvCacheParams p; } args;
void main() { mv_cache_request_compact(args.pos, args.list, args.p, MV_GLOBAL_ID(), MV_GLOBAL_SIZE()); }
#elif defined(MV_ENTRY_evict)
layout(push_constant) uniform Args { MvBufU32 lru; MvBufU32 table; MvBufU32 owner; MvBufU32 evicted; MvCacheParams p; } args;
void main() {
  mv_cache_evict(args.lru, args.table, args.owner, args.evicted, args.p, MV_GLOBAL_ID(), MV_GLOBAL_SIZE());
}
#elif defined(MV_ENTRY_place)
layout(push_constant) uniform Args { MvBufU32 lru; MvBufU32 ok; MvBufU32 staging; MvBufU32 data; MvCacheParams p; } args;
void main() { mv_cache_place(args.lru, args.ok, args.staging, args.data, args.p, MV_GLOBAL_ID(), MV_GLOBAL_SIZE()); }
#elif defined(MV_ENTRY_publish)
layout(push_constant) uniform Args {
  MvBufU32 lru; MvBufU32 list; MvBufU32 ok; MvBufU32 table; MvBufU32 owner; MvBufU32 usage; MvCacheParams p;
} args;
void main() {
  mv_cache_publish(args.lru, args.list, args.ok, args.table, args.owner, args.usage, args.p, MV_GLOBAL_ID(),
                   MV_GLOBAL_SIZE());
}
#elif defined(MV_ENTRY_run_flags)
layout(push_constant) uniform Args { MvBufU32 table; MvBufU32 flags; MvCacheParams p; } args;
void main() { mv_cache_run_flags(args.table, args.flags, args.p, MV_GLOBAL_ID(), MV_GLOBAL_SIZE()); }
#elif defined(MV_ENTRY_run_bounds)
layout(push_constant) uniform Args { MvBufU32 table; MvBufU32 pos; MvBufU32 bounds; MvCacheParams p; } args;
void main() { mv_cache_run_bounds(args.table, args.pos, args.bounds, args.p, MV_GLOBAL_ID(), MV_GLOBAL_SIZE()); }
#elif defined(MV_ENTRY_run_expand)
layout(push_constant) uniform Args { MvBufU32 table; MvBufU32 pos; MvBufU32 bounds; MvCacheParams p; } args;
void main() { mv_cache_run_expand(args.table, args.pos, args.bounds, args.p, MV_GLOBAL_ID(), MV_GLOBAL_SIZE()); }
#else
#error "define MV_ENTRY_lru_flags, _lru_scatter, _request_flags, _request_compact, _evict, _place, _publish, _run_flags, _run_bounds or _run_expand"
#endif
