#!/usr/bin/env python3
"""Executable companion of docs/SUBDIVISION-RULES.md: sections 1-3 (OpenSubdiv 3.5
Catmark and Loop with boundaries, semi-sharp creases, corners and the Chaikin option),
section 4 (CGAL Doo-Sabin), 5 (sqrt(3) as CGAL/OpenMesh), 6 (OpenMesh modified
Butterfly) and the pure cases of 7 (quad/triangle framework).

Written from the rules document only (no OpenSubdiv code), in plain Python (no numpy), so
it is slow: meant for small meshes.  Its purpose is to prove the document is exact:

    rules_reference.py IN.{obj,off} --scheme catmark|loop --levels N --out-prefix P
        [--boundary none|edge-only|edge-and-corner] [--creasing uniform|chaikin]
        [--tri-sub catmark|smooth]
    rules_reference.py IN.{obj,off} --scheme doo-sabin|sqrt3|butterfly|quadtri --levels N --out-prefix P

writes P_1.obj .. P_N.obj, to be compared with osd_oracle / cgal_oracle /
openmesh_oracle output by pointset_diff (all agree to ~1e-16 relative; see the doc).
Same tag conventions as osd_oracle (`t crease 2/1/0 a b s`, `t corner 1/1/0 v s`,
`t interpolateboundary 1/0/0 k` with k: 0 none, 1 edge-and-corner, 2 edge-only).
Manifold input only (non-manifold edges/vertices are outside this reference).
"""
import math
import struct
import sys

INF = 10.0  # Sdc::Crease::SHARPNESS_INFINITE


def f32(x):
    """Round to IEEE single precision: OpenSubdiv stores and subdivides sharpness as float."""
    return struct.unpack('f', struct.pack('f', x))[0]


def is_sharp(s):
    return s > 0.0


def is_inf(s):
    return s >= INF


def is_semi(s):
    return 0.0 < s < INF


def decrement(s):  # uniform rule (also vertex sharpness, both methods)
    if s <= 0.0:
        return 0.0
    if s >= INF:
        return INF
    return f32(s - 1.0) if s > 1.0 else 0.0


def chaikin_child(s, around):
    """Sharpness of the child of an edge (sharpness s) at its end vertex whose incident
    edges have sharpness `around` (includes this edge)."""
    if len(around) < 2:
        return decrement(s)
    if s <= 0.0:
        return 0.0
    if s >= INF:
        return INF
    semi = [x for x in around if is_semi(x)]
    if len(semi) > 1:
        tot = 0.0
        for x in semi:
            tot = f32(tot + x)
        other = f32(f32(tot - s) / (len(semi) - 1))
        s = f32(f32(0.75 * s) + f32(0.25 * other))
    s = f32(s - 1.0)
    return s if s > 0.0 else 0.0


SMOOTH, DART, CREASE, CORNER = "smooth", "dart", "crease", "corner"


def vertex_rule(vsharp, edge_sharps):
    if is_sharp(vsharp):
        return CORNER
    n = sum(1 for s in edge_sharps if is_sharp(s))
    return [SMOOTH, DART, CREASE][n] if n <= 2 else CORNER


def add(a, b, w):  # a += w*b
    a[0] += w * b[0]
    a[1] += w * b[1]
    a[2] += w * b[2]


def read_off(path):
    toks = []
    for line in open(path):
        toks += line.split('#')[0].split()
    assert toks[0] == 'OFF', 'plain ASCII OFF only'
    nv, nf = int(toks[1]), int(toks[2])
    k = 4
    P = []
    for _ in range(nv):
        P.append([float(toks[k]), float(toks[k + 1]), float(toks[k + 2])])
        k += 3
    F = []
    for _ in range(nf):
        n = int(toks[k])
        F.append([int(x) for x in toks[k + 1:k + 1 + n]])
        k += n + 1
    return P, F, [], [], -1


def read_obj(path):
    if path.lower().endswith('.off'):
        return read_off(path)
    P, F, creases, corners, ib = [], [], [], [], -1
    for line in open(path):
        t = line.split()
        if not t or t[0].startswith('#'):
            continue
        if t[0] == 'v':
            P.append([float(t[1]), float(t[2]), float(t[3])])
        elif t[0] == 'f':
            idx = []
            for tok in t[1:]:
                v = int(tok.split('/')[0])
                idx.append(v - 1 if v > 0 else len(P) + v)
            F.append(idx)
        elif t[0] == 't':
            name = t[1]
            ni, nf = [int(x) for x in t[2].split('/')[:2]]
            ints = [int(x) for x in t[3:3 + ni]]
            fl = [float(x) for x in t[3 + ni:3 + ni + nf]]
            if name == 'crease':
                for j in range(0, ni - 1, 2):
                    s = fl[min(j // 2, nf - 1)] if nf > 1 else fl[0]
                    creases.append((ints[j], ints[j + 1], f32(max(0.0, s))))
            elif name == 'corner':
                for j in range(ni):
                    s = fl[min(j, nf - 1)] if nf > 1 else fl[0]
                    corners.append((ints[j], f32(max(0.0, s))))
            elif name == 'interpolateboundary':
                ib = ints[0]
    return P, F, creases, corners, ib


class Level:
    def __init__(self, P, F, esharp, vsharp):
        self.P, self.F = P, F
        self.vsharp = vsharp                  # list per vertex
        # edges
        self.edges, self.eindex = [], {}
        self.efaces = []
        self.vedges = [[] for _ in P]
        self.vfaces = [[] for _ in P]
        for fi, f in enumerate(F):
            for k in range(len(f)):
                a, b = f[k], f[(k + 1) % len(f)]
                key = (min(a, b), max(a, b))
                if key not in self.eindex:
                    self.eindex[key] = len(self.edges)
                    self.edges.append(key)
                    self.efaces.append([])
                    self.vedges[a].append(self.eindex[key])
                    self.vedges[b].append(self.eindex[key])
                self.efaces[self.eindex[key]].append(fi)
                self.vfaces[f[k]].append(fi)
        self.esharp = [esharp.get(e, 0.0) for e in self.edges]

    def other(self, e, v):
        a, b = self.edges[e]
        return b if a == v else a


def prepare_base(P, F, creases, corners, boundary):
    es = {}
    for a, b, s in creases:
        es[(min(a, b), max(a, b))] = s
    vs = [0.0] * len(P)
    for v, s in corners:
        vs[v] = s
    L = Level(P, F, es, vs)
    for e in range(len(L.edges)):
        nf = len(L.efaces[e])
        if nf != 2:  # boundary (and non-manifold) edges are infinitely sharp in every mode
            L.esharp[e] = INF
    if boundary == 'edge-and-corner':
        for v in range(len(P)):
            if len(L.vfaces[v]) == 1 and len(L.vedges[v]) == 2:
                L.vsharp[v] = INF
    return L


def child_edge_sharpness(L, e, v, creasing):
    s = L.esharp[e]
    if creasing == 'uniform':
        return decrement(s)
    return chaikin_child(s, [L.esharp[x] for x in L.vedges[v]])


def fractional_weight(L, v, creasing, cvs, child_es):
    cnt, tot = 0, 0.0
    if is_sharp(L.vsharp[v]) and not is_sharp(cvs):
        cnt, tot = 1, L.vsharp[v]
    for i, e in enumerate(L.vedges[v]):
        s = L.esharp[e]
        if creasing == 'uniform':
            hit = is_sharp(s) and s <= 1.0
        else:
            hit = is_sharp(s) and not is_sharp(child_es[i])
        if hit:
            cnt += 1
            tot = f32(tot + s)
    if cnt == 0:
        return 0.0
    return min(1.0, f32(tot / cnt))


def refine(L, scheme, creasing, trisub):
    P, F = L.P, L.F
    nv, ne, nf = len(P), len(L.edges), len(F)
    catmark = scheme == 'catmark'
    # child sharpness of edge children, per end: cs[e] = (sharp at edges[e][0], at edges[e][1])
    cs = [(child_edge_sharpness(L, e, L.edges[e][0], creasing),
           child_edge_sharpness(L, e, L.edges[e][1], creasing)) for e in range(ne)]
    cvs = [decrement(s) for s in L.vsharp]

    # ---- face points (Catmark) ----
    fp = []
    if catmark:
        for f in F:
            c = [0.0, 0.0, 0.0]
            for v in f:
                add(c, P[v], 1.0 / len(f))
            fp.append(c)

    # ---- edge points ----
    ep = []
    for e in range(ne):
        a, b = L.edges[e]
        s = L.esharp[e]
        mid = [0.5 * (P[a][i] + P[b][i]) for i in range(3)]
        if is_sharp(s) and is_sharp(cs[e][0]) and is_sharp(cs[e][1]):
            ep.append(mid)  # crease -> crease
            continue
        # smooth mask
        sm = [0.0, 0.0, 0.0]
        faces = L.efaces[e]
        if catmark:
            if trisub == 'smooth' and len(faces) == 2 and any(len(F[f]) == 3 for f in faces):
                fw = 0.5 * sum(0.470 if len(F[f]) == 3 else 0.25 for f in faces)
                vw = 0.5 * (1.0 - 2.0 * fw)
                add(sm, P[a], vw); add(sm, P[b], vw)
                for f in faces:
                    add(sm, fp[f], fw)
            else:
                add(sm, P[a], 0.25); add(sm, P[b], 0.25)
                for f in faces:
                    add(sm, fp[f], 0.5 / len(faces))
        else:
            add(sm, P[a], 0.375); add(sm, P[b], 0.375)
            for f in faces:
                opp = [x for x in F[f] if x != a and x != b][0]
                add(sm, P[opp], 0.125 * 2.0 / len(faces))
        if not is_sharp(s):
            ep.append(sm)
        else:  # crease decaying to smooth: blend with the PARENT sharpness (not clamped)
            w = s
            ep.append([w * mid[i] + (1.0 - w) * sm[i] for i in range(3)])

    # ---- vertex points ----
    vp = []
    for v in range(nv):
        edges = L.vedges[v]
        pes = [L.esharp[e] for e in edges]
        ces = [cs[e][0] if L.edges[e][0] == v else cs[e][1] for e in edges]
        prule = vertex_rule(L.vsharp[v], pes)
        crule = vertex_rule(cvs[v], ces)

        def mask(rule, sharps):
            out = [0.0, 0.0, 0.0]
            if rule == CORNER:
                add(out, P[v], 1.0)
            elif rule == CREASE:
                add(out, P[v], 0.75)
                for e, s in zip(edges, sharps):
                    if is_sharp(s):
                        add(out, P[L.other(e, v)], 0.125)
            else:
                n = len(L.vfaces[v])
                if catmark:
                    add(out, P[v], (n - 2.0) / n)
                    for e in edges:
                        add(out, P[L.other(e, v)], 1.0 / (n * n))
                    for f in L.vfaces[v]:
                        add(out, fp[f], 1.0 / (n * n))
                else:
                    if n == 6:
                        we, wv = 0.0625, 0.625
                    else:
                        beta = 0.25 * math.cos(2.0 * math.pi / n) + 0.375
                        we = (0.625 - beta * beta) / n
                        wv = 1.0 - we * n
                    add(out, P[v], wv)
                    for e in edges:
                        add(out, P[L.other(e, v)], we)
            return out

        if prule in (SMOOTH, DART):
            vp.append(mask(SMOOTH, pes))
            continue
        pm = mask(prule, pes)
        if crule == prule:
            vp.append(pm)
            continue
        cm = mask(crule, ces)
        w = fractional_weight(L, v, creasing, cvs[v], ces)
        vp.append([w * pm[i] + (1.0 - w) * cm[i] for i in range(3)])

    # ---- child topology ----
    CP = vp + ep + fp
    eid = lambda a, b: nv + L.eindex[(min(a, b), max(a, b))]
    CF = []
    for fi, f in enumerate(F):
        n = len(f)
        if catmark:
            c = nv + ne + fi
            for k in range(n):
                CF.append([f[k], eid(f[k], f[(k + 1) % n]), c, eid(f[k - 1], f[k])])
        else:
            a, b, c = f
            eab, ebc, eca = eid(a, b), eid(b, c), eid(c, a)
            CF += [[a, eab, eca], [b, ebc, eab], [c, eca, ebc], [eab, ebc, eca]]
    ces_map = {}
    for e in range(ne):
        a, b = L.edges[e]
        for end, s in ((a, cs[e][0]), (b, cs[e][1])):
            if s > 0.0:
                key = (min(end, nv + e), max(end, nv + e))
                ces_map[key] = s
    cvsharp = cvs + [0.0] * (ne + len(fp))
    return Level(CP, CF, ces_map, cvsharp)


# ----------------------------------------------------------------------------------
# Sections 4-7: CGAL Doo-Sabin, sqrt(3) (CGAL == OpenMesh), OpenMesh modified Butterfly,
# and the quad/triangle framework (pure-quad and pure-triangle cases only).
# Plain (P, F) meshes, oriented manifold input.
# ----------------------------------------------------------------------------------
class Topo:
    def __init__(self, P, F):
        self.P, self.F = P, F
        self.he = {}                       # directed edge (a, b) -> face containing a->b
        self.nbr = [[] for _ in P]         # neighbour vertices (insertion order)
        self.vf = [[] for _ in P]
        for fi, f in enumerate(F):
            n = len(f)
            for k in range(n):
                a, b = f[k], f[(k + 1) % n]
                self.he[(a, b)] = fi
                if b not in self.nbr[a]:
                    self.nbr[a].append(b)
                if a not in self.nbr[b]:
                    self.nbr[b].append(a)
                self.vf[a].append(fi)

    def bedge(self, a, b):
        return ((a, b) in self.he) != ((b, a) in self.he)

    def bvert(self, v):
        return any(self.bedge(v, w) for w in self.nbr[v])

    def bnbrs(self, v):
        return [w for w in self.nbr[v] if self.bedge(v, w)]

    def next_in_face(self, fi, v, step=1):
        f = self.F[fi]
        return f[(f.index(v) + step) % len(f)]

    def ring(self, v, start):
        """Neighbours of an interior vertex v in rotational order, starting at `start`."""
        out, w = [start], start
        while True:
            fi = self.he[(v, w)]
            w = self.next_in_face(fi, v, -1)  # previous vertex of v in that face
            if w == start:
                return out
            out.append(w)

    def faces_around(self, v):
        """Faces around an interior vertex v in CCW order."""
        f0 = self.vf[v][0]
        out, fi = [f0], f0
        while True:
            u = self.next_in_face(fi, v, -1)
            fi = self.he[(v, u)]
            if fi == f0:
                return out
            out.append(fi)


def lin(*terms):
    out = [0.0, 0.0, 0.0]
    for w, p in terms:
        add(out, p, w)
    return out


def doo_sabin_step(P, F):
    """CGAL DooSabin_mask_3 + DQQ_1step (boundary faces dropped)."""
    T = Topo(P, F)
    NP, cid = [], {}
    for fi, f in enumerate(F):
        n = len(f)
        for k in range(n):
            cv = [0.0, 0.0, 0.0]
            if n == 4:
                for j, w in enumerate((9, 3, 1, 3)):
                    add(cv, P[f[(k + j) % 4]], w)
                cv = [c / 16 for c in cv]
            else:
                for j in range(n):
                    a = (5.0 / n) + 1 if j == 0 else (3 + 2 * math.cos(2 * j * math.pi / n)) / n
                    add(cv, P[f[(k + j) % n]], a)
                cv = [c / 4 for c in cv]
            cid[(fi, f[k])] = len(NP)
            NP.append(cv)
    NF = [[cid[(fi, v)] for v in f] for fi, f in enumerate(F)]           # F-faces
    for (a, b), f in T.he.items():                                       # E-faces
        g = T.he.get((b, a))
        if g is not None and a < b:
            NF.append([cid[(g, a)], cid[(g, b)], cid[(f, b)], cid[(f, a)]])
    for v in range(len(P)):                                              # V-faces
        if T.vf[v] and not T.bvert(v):
            NF.append([cid[(fi, v)] for fi in T.faces_around(v)])
    return NP, NF


def sqrt3_step(P, F, refine_border):
    """Kobbelt sqrt(3) as CGAL Sqrt3_1step / OpenMesh Sqrt3T: boundary refined only when
    refine_border (every second step, counting from 0)."""
    T = Topo(P, F)
    nv = len(P)
    NP = []
    for v in range(nv):
        if T.bvert(v):
            if refine_border:
                a, b = T.bnbrs(v)
                NP.append(lin((4 / 27, P[a]), (19 / 27, P[v]), (4 / 27, P[b])))
            else:
                NP.append(list(P[v]))
        else:
            n = len(T.nbr[v])
            al = (4.0 - 2.0 * math.cos(2.0 * math.pi / n)) / 9.0
            q = lin((1.0 - al, P[v]))
            for w in T.nbr[v]:
                add(q, P[w], al / n)
            NP.append(q)
    tris = []
    for fi, f in enumerate(F):
        bk = [k for k in range(3) if T.bedge(f[k], f[(k + 1) % 3])]
        if refine_border and bk:
            k = bk[0]
            a, b, x = f[k], f[(k + 1) % 3], f[(k + 2) % 3]
            ao = [w for w in T.bnbrs(a) if w != b][0]
            bo = [w for w in T.bnbrs(b) if w != a][0]
            pa = len(NP); NP.append(lin((16 / 27, P[a]), (10 / 27, P[b]), (1 / 27, P[ao])))
            pb = len(NP); NP.append(lin((16 / 27, P[b]), (10 / 27, P[a]), (1 / 27, P[bo])))
            tris += [[a, pa, x], [pa, pb, x], [pb, b, x]]
        else:
            c = len(NP); NP.append(lin(*[(1 / 3, P[v]) for v in f]))
            tris += [[f[0], f[1], c], [f[1], f[2], c], [f[2], f[0], c]]
    where = {}
    for ti, t in enumerate(tris):
        for k in range(3):
            where[(t[k], t[(k + 1) % 3])] = ti
    for (u, v) in list(T.he.keys()):               # flip old interior edges
        if u < v and (v, u) in T.he:
            t1, t2 = where[(u, v)], where[(v, u)]
            w1 = [x for x in tris[t1] if x not in (u, v)][0]
            w2 = [x for x in tris[t2] if x not in (u, v)][0]
            tris[t1], tris[t2] = [u, w2, w1], [v, w1, w2]
    return NP, tris


def loop_topology(F, nv, eid):
    out = []
    for a, b, c in F:
        eab, ebc, eca = eid[(min(a, b), max(a, b))], eid[(min(b, c), max(b, c))], eid[(min(c, a), max(c, a))]
        out += [[a, eab, eca], [b, ebc, eab], [c, eca, ebc], [eab, ebc, eca]]
    return out


def butterfly_weights(K):
    if K == 3:
        return [5 / 12, -1 / 12, -1 / 12]
    if K == 4:
        return [3 / 8, 0.0, -1 / 8, 0.0]
    return [(0.25 + math.cos(2 * math.pi * j / K) + 0.5 * math.cos(4 * math.pi * j / K)) / K for j in range(K)]


def butterfly_step(P, F):
    """OpenMesh 9 ModifiedButterflyT."""
    T = Topo(P, F)
    nv = len(P)
    NP = [list(p) for p in P]
    eid = {}
    val = [len(T.nbr[v]) for v in range(nv)]
    bv = [T.bvert(v) for v in range(nv)]

    def apex_or_ghost(x, b, y):
        """vertex across edge (x, b) from triangle (x, b, y), or the ghost x + b - y"""
        for d in ((x, b), (b, x)):
            fi = T.he.get(d)
            if fi is not None and y not in F[fi]:
                return P[[z for z in F[fi] if z not in (x, b)][0]]
        return [P[x][i] + P[b][i] - P[y][i] for i in range(3)]

    for (a0, a1) in list(T.he.keys()) + [(b, a) for (a, b) in T.he if (b, a) not in T.he]:
        key = (min(a0, a1), max(a0, a1))
        if key in eid:
            continue
        eid[key] = len(NP)
        if T.bedge(a0, a1):
            o0 = [w for w in T.bnbrs(a0) if w != a1][0]
            o1 = [w for w in T.bnbrs(a1) if w != a0][0]
            NP.append(lin((9 / 16, P[a0]), (9 / 16, P[a1]), (-1 / 16, P[o0]), (-1 / 16, P[o1])))
            continue
        fa, fb = T.he[(a0, a1)], T.he[(a1, a0)]
        b0 = [z for z in F[fa] if z not in (a0, a1)][0]
        b1 = [z for z in F[fb] if z not in (a0, a1)][0]
        v0, v1 = val[a0], val[a1]
        if (v0 == 6 and v1 == 6) or (bv[a0] and v1 == 6) or (bv[a1] and v0 == 6) or (bv[a0] and bv[a1]):
            cs = [apex_or_ghost(a1, b0, a0), apex_or_ghost(a0, b0, a1),
                  apex_or_ghost(a1, b1, a0), apex_or_ghost(a0, b1, a1)]
            q = lin((0.5, P[a0]), (0.5, P[a1]), (0.125, P[b0]), (0.125, P[b1]))
            for c in cs:
                add(q, c, -1 / 16)
            NP.append(q)
        else:
            q, nrm = [0.0, 0.0, 0.0], 0
            for a, other in ((a0, a1), (a1, a0)):
                if val[a] != 6 and not bv[a]:
                    w = butterfly_weights(val[a])
                    for j, u in enumerate(T.ring(a, other)):
                        add(q, P[u], w[j])
                    add(q, P[a], 1.0 - sum(w))
                    nrm += 1
            NP.append([c / nrm for c in q])
    return NP, loop_topology(F, nv, eid)


def quadtri_step(P, F):
    """Quad/triangle framework (section 7): linear subdivision, centroid averaging, then
    v' = v + w (cbar - v).  Only the pure cases (all quads or all triangles around a vertex)
    have a defined w here; boundaries are not handled."""
    T0 = Topo(P, F)
    nv = len(P)
    NP = [list(p) for p in P]
    eid = {}
    for (a, b) in T0.he:
        key = (min(a, b), max(a, b))
        if key not in eid:
            eid[key] = len(NP)
            NP.append(lin((0.5, P[a]), (0.5, P[b])))
    NF = []
    for f in F:
        if len(f) == 3:
            NF += loop_topology([f], nv, eid)
        else:
            c = len(NP); NP.append(lin(*[(1.0 / len(f), P[v]) for v in f]))
            n = len(f)
            for k in range(n):
                e1 = eid[(min(f[k], f[(k + 1) % n]), max(f[k], f[(k + 1) % n]))]
                e0 = eid[(min(f[k - 1], f[k]), max(f[k - 1], f[k]))]
                NF.append([f[k], e1, c, e0])
    T = Topo(NP, NF)
    out = []
    for v in range(len(NP)):
        fs = T.vf[v]
        nq = sum(1 for fi in fs if len(NF[fi]) == 4)
        nt = len(fs) - nq
        cbar = [0.0, 0.0, 0.0]
        for fi in fs:
            f = NF[fi]
            if len(f) == 4:
                for u in f:
                    add(cbar, NP[u], 0.25 / len(fs))
            else:
                for u in f:
                    add(cbar, NP[u], (0.25 if u == v else 0.375) / len(fs))
        n = len(fs)
        if nt == 0:
            w = 4.0 / n
        elif nq == 0:
            b = 0.375 + 0.25 * math.cos(2.0 * math.pi / n)
            w = (8.0 / 3.0) * (0.625 - b * b)
        else:
            raise SystemExit('quadtri: mixed quad/triangle vertex: weight not specified (see section 7)')
        out.append([NP[v][i] + w * (cbar[i] - NP[v][i]) for i in range(3)])
    return out, NF


class Plain:
    def __init__(self, P, F):
        self.P, self.F = P, F


def write_obj(path, L):
    with open(path, 'w') as out:
        for p in L.P:
            out.write('v %.17g %.17g %.17g\n' % tuple(p))
        for f in L.F:
            out.write('f ' + ' '.join(str(v + 1) for v in f) + '\n')


def main(argv):
    args = {}
    pos = []
    i = 1
    while i < len(argv):
        if argv[i].startswith('--'):
            args[argv[i][2:]] = argv[i + 1]
            i += 2
        else:
            pos.append(argv[i])
            i += 1
    P, F, creases, corners, ib = read_obj(pos[0])
    scheme = args['scheme']
    levels = int(args.get('levels', '1'))
    if scheme in ('doo-sabin', 'sqrt3', 'butterfly', 'quadtri'):
        for lev in range(1, levels + 1):
            if scheme == 'doo-sabin':
                P, F = doo_sabin_step(P, F)
            elif scheme == 'sqrt3':
                P, F = sqrt3_step(P, F, refine_border=(lev % 2 == 0))
            elif scheme == 'butterfly':
                P, F = butterfly_step(P, F)
            else:
                P, F = quadtri_step(P, F)
            write_obj('%s_%d.obj' % (args['out-prefix'], lev), Plain(P, F))
        return
    boundary = {0: 'none', 1: 'edge-and-corner', 2: 'edge-only'}.get(ib, 'edge-only')
    boundary = args.get('boundary', boundary)
    L = prepare_base(P, F, creases, corners, boundary)
    for lev in range(1, int(args.get('levels', '1')) + 1):
        L = refine(L, args['scheme'], args.get('creasing', 'uniform'), args.get('tri-sub', 'catmark'))
        write_obj('%s_%d.obj' % (args['out-prefix'], lev), L)


if __name__ == '__main__':
    main(sys.argv)
