# spot_udim.obj from spot (tests/cli/cli_bake_udim.sh, tests/cli/cli_bake_window.sh):
# each face moved whole UV tiles by the quadrant of its 3D centroid (tiles
# 1001, 1002, 1011, 1012); the %.17g keeps shared corners of faces in one
# tile bit-equal.
#   awk -f tests/cli/spot_udim.awk spot_quadrangulated.obj > spot_udim.obj

/^v / { nv++; X[nv] = $2; Z[nv] = $4; print; next }
/^vt / { nt++; U[nt] = $2; V[nt] = $3; next }
/^f / {
    cx = 0; cz = 0
    for (i = 2; i <= NF; i++) { split($i, p, "/"); cx += X[p[1]]; cz += Z[p[1]]; vi[i] = p[1]; ti[i] = p[2] }
    t = (cx >= 0 ? 1 : 0) + (cz >= 0 ? 2 : 0); line = "f"
    for (i = 2; i <= NF; i++) line = line " " vi[i] "/" (ti[i] + t * nt)
    F[++nf] = line; next
}
END {
    for (t = 0; t < 4; t++) for (i = 1; i <= nt; i++) printf "vt %.17g %.17g\n", U[i] + t % 2, V[i] + int(t / 2)
    for (i = 1; i <= nf; i++) print F[i]
}