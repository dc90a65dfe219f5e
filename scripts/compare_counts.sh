#!/usr/bin/env bash
# Voxel and DAG node counts of meshes in both voxelization rules on the min-corner grid (the convention of
# the voxcom tools), for comparison with other tools' builds: one `megavox build --json` per mesh,
# resolution, rule and encoding (svdag, then ssvdag), summarised as Markdown rows; the full JSON
# (per-level counts) goes to OUT.jsonl.
# Usage: scripts/compare_counts.sh OUT.jsonl "2K 4K" mesh.ply...   (default meshes: those of $MEGAVOX_TEST_DATA, default ../shared/data)
set -euo pipefail
cd "$(dirname "$0")/.."
out=${1:-build/compare_counts.jsonl}
resolutions=${2:-"2K 4K"}
shift 2 || true
meshes=("$@")
if [ ${#meshes[@]} -eq 0 ]; then meshes=("${MEGAVOX_TEST_DATA:-../shared/data}"/meshes_*/*.ply); fi
: >"$out"
echo "| mesh | res | rule | voxels | SVO nodes | SVDAG nodes | SSVDAG nodes | SVDAG bits/voxel | SSVDAG bits/voxel | SSVDAG/SVDAG bytes |"
echo "|---|---|---|---:|---:|---:|---:|---:|---:|---:|"
for mesh in "${meshes[@]}"; do
  for res in $resolutions; do
    for rule in conservative thin; do
      for fmt in svdag ssvdag; do
        build/megavox build "$mesh" --resolution "$res" --voxelize "$rule" --grid-origin min --format "$fmt" \
          -o build/compare.mvx --quiet --json | node -e 'let s="";process.stdin.on("data",d=>s+=d).on("end",()=>console.log(JSON.stringify(JSON.parse(s))))' >>"$out"
      done
      tail -n 2 "$out" | node -e '
        const [a, b] = require("fs").readFileSync(0, "utf8").trim().split("\n").map(JSON.parse);
        const svo = a.svo_nodes_per_level.slice(2).reduce((x, y) => x + y, 0);
        const name = a.input.split("/").pop().replace(/\.ply$/, "");
        console.log(`| ${name} | ${a.resolution} | ${a.voxelize} | ${a.voxels} | ${svo} | ${a.nodes_total} | ${b.nodes_total} | ` +
                    `${a.bits_per_voxel.toFixed(3)} | ${b.bits_per_voxel.toFixed(3)} | ${(b.bytes / a.bytes).toFixed(3)} |`);'
    done
  done
done
rm -f build/compare.mvx
