#!/usr/bin/env bash
# The build table of BENCHMARKS.md: `megavox bench build` per mesh at one resolution, thin then conservative
# (min corner, ssvdag, default budgets), with voxcom's voxelizer beside the thin run when it is built
# (build/peers/voxcom; scripts/bench.sh builds it). Prints Markdown rows; the full JSON goes to OUT.jsonl.
# Usage: scripts/build_table.sh OUT.jsonl RES mesh.ply...   (default meshes: those of $MEGAVOX_TEST_DATA, default ../shared/data)
set -euo pipefail
cd "$(dirname "$0")/.."
out=${1:-build/build_table.jsonl}
res=${2:-16K}
shift 2 || true
meshes=("$@")
if [ ${#meshes[@]} -eq 0 ]; then meshes=("${MEGAVOX_TEST_DATA:-../shared/data}"/meshes_*/*.ply); fi
: >"$out"
echo "| mesh | triangles | res | rule | voxels | DAG nodes | megavox s | Mvoxels/s | peak RSS GB | voxcom s | voxcom RSS GB | megavox / voxcom time | RSS ratio | conservative / thin time |"
echo "|---|---:|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|"
for mesh in "${meshes[@]}"; do
  for rule in thin conservative; do
    build/megavox bench build "$mesh" --resolution "$res" --voxelize "$rule" --grid-origin min --format ssvdag --json \
      2>/dev/null | node -e 'let s="";process.stdin.on("data",d=>s+=d).on("end",()=>console.log(JSON.stringify(JSON.parse(s))))' >>"$out"
  done
  tail -n 2 "$out" | node -e '
    const rows = require("fs").readFileSync(0, "utf8").trim().split("\n").map(JSON.parse);
    const thin = rows[0].wall_seconds;
    for (const r of rows) {
      const name = r.mesh.split("/").pop().replace(/\.ply$/, "");
      const p = r.peer_status === "ran" ? r.peer : null;
      const gb = (b) => (b / 1e9).toFixed(2);
      console.log(`| ${name} | ${r.triangles} | ${r.resolution} | ${r.voxelize} | ${r.voxels} | ${r.nodes_total} | ` +
                  `${r.wall_seconds.toFixed(1)} | ${(r.voxels_per_s / 1e6).toFixed(1)} | ${gb(r.peak_rss_bytes)} | ` +
                  (p ? `${p.wall_seconds.toFixed(1)} | ${gb(p.max_rss_bytes)} | ${p.wall_ratio.toFixed(2)} | ${p.rss_ratio.toFixed(2)} | `
                     : "– | – | – | – | ") +
                  (r.voxelize === "conservative" ? `${(r.wall_seconds / thin).toFixed(2)} |` : "|"));
    }'
done
