// OpenCL entry points of SVO level building and DAG reduction (bodies: common/dag.h).
#include "common/dag.h"

#define MV_ID MV_GLOBAL_ID(), MV_GLOBAL_SIZE()

__kernel void svo_flags(__global ulong* keys, __global uint* flags, MvDagParams p) {
  mv_svo_flags(keys, flags, p, MV_ID);
}
__kernel void svo_parents(__global ulong* keys, __global uint* pos, __global ulong* pkeys, __global uint* pmask,
                          __global uint* pfirst, MvDagParams p) {
  mv_svo_parents(keys, pos, pkeys, pmask, pfirst, p, MV_ID);
}
__kernel void brick_levels(__global ulong* bricks, __global uint* mask2, __global uint* count, MvDagParams p) {
  mv_brick_levels(bricks, mask2, count, p, MV_ID);
}
__kernel void brick_leaves(__global ulong* bricks, __global uint* first2, __global uint* mask1, MvDagParams p) {
  mv_brick_leaves(bricks, first2, mask1, p, MV_ID);
}
__kernel void brick_gather(__global ulong* src, __global uint* order, __global ulong* dst, MvDagParams p) {
  mv_brick_gather(src, order, dst, p, MV_ID);
}
__kernel void dag_hash(__global uint* mask, __global uint* first, __global uint* cid, __global ulong* hashes,
                       __global uint* order, MvDagParams p) {
  mv_dag_hash(mask, first, cid, hashes, order, p, MV_ID);
}
__kernel void dag_runs(__global ulong* hashes, __global uint* flags, MvDagParams p) {
  mv_dag_runs(hashes, flags, p, MV_ID);
}
__kernel void dag_assign(__global ulong* hashes, __global uint* order, __global uint* run, __global uint* id,
                         __global uint* rep, MvDagParams p) {
  mv_dag_assign(hashes, order, run, id, rep, p, MV_ID);
}
__kernel void dag_verify(__global uint* mask, __global uint* first, __global uint* cid, __global uint* id,
                         __global uint* rep, __global uint* collided, MvDagParams p) {
  mv_dag_verify(mask, first, cid, id, rep, collided, p, MV_ID);
}

#include "common/ssvdag.h"

__kernel void ssvdag_canon(__global uint* mask, __global uint* mtab, __global uint* first, __global uint* cid,
                           __global uint* crow, __global uint* row, __global ulong* hashes, __global uint* order,
                           MvDagParams p) {
  mv_ssvdag_canon(mask, mtab, first, cid, crow, row, hashes, order, p, MV_ID);
}
__kernel void brick_keys(__global uint* mask, __global uint* first, __global uint* cmask, __global ulong* keys,
                         __global uint* order, MvDagParams p) {
  mv_brick_keys(mask, first, cmask, keys, order, p, MV_ID);
}
__kernel void brick_canon(__global uint* mask, __global uint* mtab, __global uint* first, __global uint* cmask,
                          __global uint* rep, __global ulong* keys, __global uint* row, __global uint* order,
                          MvDagParams p) {
  mv_brick_canon(mask, mtab, first, cmask, rep, keys, row, order, p, MV_ID);
}
__kernel void brick_emit(__global uint* mask, __global uint* first, __global uint* cmask, __global uint* mtab,
                         __global uint* crank, __global uint* row, __global uint* rep, __global uint* out_mask,
                         __global ulong* out_entry, MvDagParams p) {
  mv_brick_emit(mask, first, cmask, mtab, crank, row, rep, out_mask, out_entry, p, MV_ID);
}
__kernel void brick_orient(__global uint* id, __global uint* cls, __global uint* crow, __global uint* row,
                           MvDagParams p) {
  mv_brick_orient(id, cls, crow, row, p, MV_ID);
}
__kernel void ssvdag_verify(__global uint* mask, __global uint* first, __global uint* cid, __global uint* crow,
                            __global uint* row, __global uint* id, __global uint* rep, __global uint* collided,
                            MvDagParams p) {
  mv_ssvdag_verify(mask, first, cid, crow, row, id, rep, collided, p, MV_ID);
}
__kernel void leaf_table(__global uint* table, MvDagParams p) { mv_leaf_table(table, MV_ID); }
__kernel void leaf_present(__global uint* mask, __global uint* table, __global uint* present, MvDagParams p) {
  mv_leaf_present(mask, table, present, p, MV_ID);
}
__kernel void leaf_classes(__global uint* rank, __global uint* class_mask, MvDagParams p) {
  mv_leaf_classes(rank, class_mask, MV_ID);
}
__kernel void gather_slots(__global uint* slot_node, __global uint* slot_tag, __global uint* id, __global uint* row,
                           __global uint* out_id, __global uint* out_row, MvDagParams p) {
  mv_gather_slots(slot_node, slot_tag, id, row, out_id, out_row, p, MV_ID);
}
__kernel void dag_emit(__global uint* mask, __global uint* first, __global uint* cid, __global uint* crow,
                       __global uint* row, __global uint* rep, __global uint* out_mask, __global ulong* out_entry,
                       MvDagParams p) {
  mv_dag_emit(mask, first, cid, crow, row, rep, out_mask, out_entry, p, MV_ID);
}
