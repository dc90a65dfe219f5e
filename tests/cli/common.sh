# What the CLI test scripts share (sourced): a scratch folder removed at exit, fail(), and a tetrahedron PLY.
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
