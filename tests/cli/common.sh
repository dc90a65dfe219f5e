# What the CLI test scripts share (sourced): a scratch folder removed at exit, fail(), a tetrahedron PLY and a
# coloured lattice cloud, a bumpy sphere.
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

# write_sphere_ply PATH ROWS [rgb]: a bumpy closed sphere of 2 * ROWS^2 triangles, ascii; with rgb, vertex
# colours by position (so every cube of a build in cubes gets colours of its own).
write_sphere_ply() {
  python3 - "$@" <<'PY'
import math, sys
path, rows, rgb = sys.argv[1], int(sys.argv[2]), len(sys.argv) > 3 and sys.argv[3] == "rgb"
cols = rows
v, f = [], []
for i in range(rows + 1):
    t = math.pi * i / rows
    for j in range(cols):
        p = 2 * math.pi * j / cols
        r = 1 + 0.12 * math.sin(4 * t) * math.cos(5 * p)
        v.append((r * math.sin(t) * math.cos(p), r * math.cos(t), r * math.sin(t) * math.sin(p)))
for i in range(rows):
    for j in range(cols):
        a, b = i * cols + j, i * cols + (j + 1) % cols
        f += [(a, a + cols, b), (b, a + cols, b + cols)]
with open(path, "w") as out:
    props = "property uchar red\nproperty uchar green\nproperty uchar blue\n" if rgb else ""
    out.write(f"ply\nformat ascii 1.0\nelement vertex {len(v)}\nproperty float x\nproperty float y\nproperty float z\n"
              f"{props}element face {len(f)}\nproperty list uchar int vertex_indices\nend_header\n")
    for x, y, z in v:
        tail = "".join(f" {min(255, int(110 * (c + 1.2)))}" for c in (x, y, z)) if rgb else ""
        out.write(f"{x:.6f} {y:.6f} {z:.6f}{tail}\n")
    out.writelines(f"3 {a} {b} {c}\n" for a, b, c in f)
PY
}
