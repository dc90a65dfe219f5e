# What the CLI test scripts share (sourced): a scratch folder removed at exit, fail(), a tetrahedron PLY and a
# coloured lattice cloud.
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
fail() { echo "FAIL: $*" >&2; exit 1; }

# write_tetra_ply PATH: a closed tetrahedron with unit edges along the axes, ascii.
write_tetra_ply() {
  cat >"$1" <<'PLY'
ply
format ascii 1.0
element vertex 4
property float x
property float y
property float z
element face 4
property list uchar int vertex_indices
end_header
0 0 0
1 0 0
0 1 0
0 0 1
3 0 2 1
3 0 1 3
3 0 3 2
3 1 2 3
PLY
}

# write_lattice_ply PATH N STEP: an N x N x N lattice cloud, ascii: point (x + 0.5, y + 0.25, z) coloured
# (x * STEP, y * STEP, z * STEP).
write_lattice_ply() {
  local n=$2 step=$3 x y z
  {
    echo ply; echo "format ascii 1.0"; echo "element vertex $((n * n * n))"
    echo "property float x"; echo "property float y"; echo "property float z"
    echo "property uchar red"; echo "property uchar green"; echo "property uchar blue"; echo end_header
    for x in $(seq 0 $((n - 1))); do for y in $(seq 0 $((n - 1))); do for z in $(seq 0 $((n - 1))); do
      echo "$x.5 $y.25 $z $((x * step)) $((y * step)) $((z * step))"
    done; done; done
  } > "$1"
}
