// Vulkan entry points of SVO level building and DAG reduction, one module per -DMV_ENTRY_<name>
// (bodies: common/dag.h).
#version 460
#extension GL_GOOGLE_include_directive : require
#include "common/mv_glsl_prelude.h"
#include "common/dag.h"
#include "common/ssvdag.h"

#define MV_ID MV_GLOBAL_ID(), MV_GLOBAL_SIZE()

#if defined(MV_ENTRY_svo_flags)
layout(push_constant) uniform Args { MvBufU64 keys; MvBufU32 flags; MvDagParams p; } a;
void main() { mv_svo_flags(a.keys, a.flags, a.p, MV_ID); }
#elif defined(MV_ENTRY_svo_parents)
layout(push_constant) uniform Args {
  MvBufU64 keys; MvBufU32 pos; MvBufU64 pkeys; MvBufU32 pmask; MvBufU32 pfirst; MvDagParams p;
} a;
void main() { mv_svo_parents(a.keys, a.pos, a.pkeys, a.pmask, a.pfirst, a.p, MV_ID); }
#elif defined(MV_ENTRY_dag_hash)
layout(push_constant) uniform Args {
  MvBufU32 mask; MvBufU32 first; MvBufU32 cid; MvBufU64 hashes; MvBufU32 order; MvDagParams p;
} a;
void main() { mv_dag_hash(a.mask, a.first, a.cid, a.hashes, a.order, a.p, MV_ID); }
#elif defined(MV_ENTRY_dag_runs)
layout(push_constant) uniform Args { MvBufU64 hashes; MvBufU32 flags; MvDagParams p; } a;
void main() { mv_dag_runs(a.hashes, a.flags, a.p, MV_ID); }
#elif defined(MV_ENTRY_dag_assign)
layout(push_constant) uniform Args {
  MvBufU64 hashes; MvBufU32 order; MvBufU32 run; MvBufU32 id; MvBufU32 rep; MvDagParams p;
} a;
void main() { mv_dag_assign(a.hashes, a.order, a.run, a.id, a.rep, a.p, MV_ID); }
#elif defined(MV_ENTRY_dag_verify)
layout(push_constant) uniform Args {
  MvBufU32 mask; MvBufU32 first; MvBufU32 cid; MvBufU32 id; MvBufU32 rep; MvBufU32 collided; MvDagParams p;
} a;
void main() { mv_dag_verify(a.mask, a.first, a.cid, a.id, a.rep, a.collided, a.p, MV_ID); }
#elif defined(MV_ENTRY_ssvdag_canon)
layout(push_constant) uniform Args {
  MvBufU32 mask; MvBufU32 mtab; MvBufU32 first; MvBufU32 cid; MvBufU32 crow; MvBufU32 row; MvBufU64 hashes;
  MvBufU32 order; MvDagParams p;
} a;
void main() { mv_ssvdag_canon(a.mask, a.mtab, a.first, a.cid, a.crow, a.row, a.hashes, a.order, a.p, MV_ID); }
#elif defined(MV_ENTRY_brick_levels)
layout(push_constant) uniform Args { MvBufU64 bricks; MvBufU32 mask2; MvBufU32 count; MvDagParams p; } a;
void main() { mv_brick_levels(a.bricks, a.mask2, a.count, a.p, MV_ID); }
#elif defined(MV_ENTRY_brick_leaves)
layout(push_constant) uniform Args { MvBufU64 bricks; MvBufU32 first2; MvBufU32 mask1; MvDagParams p; } a;
void main() { mv_brick_leaves(a.bricks, a.first2, a.mask1, a.p, MV_ID); }
#elif defined(MV_ENTRY_brick_gather)
layout(push_constant) uniform Args { MvBufU64 src; MvBufU32 order; MvBufU64 dst; MvDagParams p; } a;
void main() { mv_brick_gather(a.src, a.order, a.dst, a.p, MV_ID); }
#elif defined(MV_ENTRY_brick_keys)
layout(push_constant) uniform Args {
  MvBufU32 mask; MvBufU32 first; MvBufU32 cmask; MvBufU64 keys; MvBufU32 order; MvDagParams p;
} a;
void main() { mv_brick_keys(a.mask, a.first, a.cmask, a.keys, a.order, a.p, MV_ID); }
#elif defined(MV_ENTRY_brick_canon)
layout(push_constant) uniform Args {
  MvBufU32 mask; MvBufU32 mtab; MvBufU32 first; MvBufU32 cmask; MvBufU32 rep; MvBufU64 keys; MvBufU32 row;
  MvBufU32 order; MvDagParams p;
} a;
void main() { mv_brick_canon(a.mask, a.mtab, a.first, a.cmask, a.rep, a.keys, a.row, a.order, a.p, MV_ID); }
#elif defined(MV_ENTRY_brick_emit)
layout(push_constant) uniform Args {
  MvBufU32 mask; MvBufU32 first; MvBufU32 cmask; MvBufU32 mtab; MvBufU32 crank; MvBufU32 row; MvBufU32 rep;
  MvBufU32 out_mask; MvBufU64 out_entry; MvDagParams p;
} a;
void main() {
  mv_brick_emit(a.mask, a.first, a.cmask, a.mtab, a.crank, a.row, a.rep, a.out_mask, a.out_entry, a.p, MV_ID);
}
#elif defined(MV_ENTRY_brick_orient)
layout(push_constant) uniform Args {
  MvBufU32 id; MvBufU32 cls; MvBufU32 crow; MvBufU32 row; MvDagParams p;
} a;
void main() { mv_brick_orient(a.id, a.cls, a.crow, a.row, a.p, MV_ID); }
#elif defined(MV_ENTRY_ssvdag_verify)
layout(push_constant) uniform Args {
  MvBufU32 mask; MvBufU32 first; MvBufU32 cid; MvBufU32 crow; MvBufU32 row; MvBufU32 id; MvBufU32 rep;
  MvBufU32 collided; MvDagParams p;
} a;
void main() { mv_ssvdag_verify(a.mask, a.first, a.cid, a.crow, a.row, a.id, a.rep, a.collided, a.p, MV_ID); }
#elif defined(MV_ENTRY_leaf_table)
layout(push_constant) uniform Args { MvBufU32 table; MvDagParams p; } a;
void main() { mv_leaf_table(a.table, MV_ID); }
#elif defined(MV_ENTRY_leaf_present)
layout(push_constant) uniform Args { MvBufU32 mask; MvBufU32 table; MvBufU32 present; MvDagParams p; } a;
void main() { mv_leaf_present(a.mask, a.table, a.present, a.p, MV_ID); }
#elif defined(MV_ENTRY_leaf_classes)
layout(push_constant) uniform Args { MvBufU32 rank; MvBufU32 class_mask; MvDagParams p; } a;
void main() { mv_leaf_classes(a.rank, a.class_mask, MV_ID); }
#elif defined(MV_ENTRY_gather_slots)
layout(push_constant) uniform Args {
  MvBufU32 slot_node; MvBufU32 slot_tag; MvBufU32 id; MvBufU32 row; MvBufU32 out_id; MvBufU32 out_row; MvDagParams p;
} a;
void main() { mv_gather_slots(a.slot_node, a.slot_tag, a.id, a.row, a.out_id, a.out_row, a.p, MV_ID); }
#elif defined(MV_ENTRY_dag_emit)
layout(push_constant) uniform Args {
  MvBufU32 mask; MvBufU32 first; MvBufU32 cid; MvBufU32 crow; MvBufU32 row; MvBufU32 rep; MvBufU32 out_mask;
  MvBufU64 out_entry; MvDagParams p;
} a;
void main() { mv_dag_emit(a.mask, a.first, a.cid, a.crow, a.row, a.rep, a.out_mask, a.out_entry, a.p, MV_ID); }
#else
#error "define one MV_ENTRY_<name>"
#endif
