// OpenCL entry points of the page cache's update pass (bodies: common/page_cache.h).
#include "common/page_cache.h"

__kernel void cache_lru_flags(__global uint* usage, __global uint* lru, __global uint* flags, MvCacheParams p) {
  mv_cache_lru_flags(usage, lru, flags, p, MV_GLOBAL_ID(), MV_GLOBAL_SIZE());
}

__kernel void cache_lru_scatter(__global uint* lru, __global uint* pos, __global uint* next, MvCacheParams p) {
  mv_cache_lru_scatter(lru, pos, next, p, MV_GLOBAL_ID(), MV_GLOBAL_SIZE());
}

__kernel void cache_request_flags(__global uint* request, __global uint* table, __global uint* flags,
                                  MvCacheParams p) {
  mv_cache_request_flags(request, table, flags, p, MV_GLOBAL_ID(), MV_GLOBAL_SIZE());
}

__kernel void cache_request_compact(__global uint* pos, __global uint* list, MvCacheParams p) {
  mv_cache_request_compact(pos, list, p, MV_GLOBAL_ID(), MV_GLOBAL_SIZE());
}

__kernel void cache_evict(__global uint* lru, __global uint* table, __global uint* owner, __global uint* evicted,
                          MvCacheParams p) {
  mv_cache_evict(lru, table, owner, evicted, p, MV_GLOBAL_ID(), MV_GLOBAL_SIZE());
}

__kernel void cache_place(__global uint* lru, __global uint* ok, __global uint* staging, __global uint* data,
                          MvCacheParams p) {
  mv_cache_place(lru, ok, staging, data, p, MV_GLOBAL_ID(), MV_GLOBAL_SIZE());
}

__kernel void cache_publish(__global uint* lru, __global uint* list, __global uint* ok, __global uint* table,
                            __global uint* owner, __global uint* usage, MvCacheParams p) {
  mv_cache_publish(lru, list, ok, table, owner, usage, p, MV_GLOBAL_ID(), MV_GLOBAL_SIZE());
}

__kernel void cache_run_flags(__global uint* table, __global uint* flags, MvCacheParams p) {
  mv_cache_run_flags(table, flags, p, MV_GLOBAL_ID(), MV_GLOBAL_SIZE());
}

__kernel void cache_run_bounds(__global uint* table, __global uint* pos, __global uint* bounds, MvCacheParams p) {
  mv_cache_run_bounds(table, pos, bounds, p, MV_GLOBAL_ID(), MV_GLOBAL_SIZE());
}

__kernel void cache_run_expand(__global uint* table, __global uint* pos, __global uint* bounds, MvCacheParams p) {
  mv_cache_run_expand(table, pos, bounds, p, MV_GLOBAL_ID(), MV_GLOBAL_SIZE());
}
