/* Sharpness rules (crease.h). */
#include "core/schemes/crease_internal.h"

float st_crease_decay(float s)
{
    if (s >= ST_SHARP_INFINITE) return ST_SHARP_INFINITE;
    return s > 1.0f ? s - 1.0f : 0.0f;
}

float st_crease_edge_sharpness(const st_subdiv_view *sv, uint32_t d, unsigned l)
{
    const st_map *m = sv->map;
    if (st_is_boundary(m, d) || st_is_boundary(m, st_beta0(m, d, l))) return ST_SHARP_INFINITE;
    return st_subdiv_edge_sharpness(sv, d, l);
}

float st_crease_vertex_sharpness(const st_subdiv_view *sv, uint32_t d, unsigned l)
{
    const st_map *m = sv->map;
    float s = st_subdiv_vertex_sharpness(sv, st_vert(m, d, l), l);
    if (sv->opts.boundary == ST_BOUNDARY_EDGE_AND_CORNER) {
        /* A boundary vertex with a single real face. */
        unsigned real = 0, bnd = 0;
        uint32_t x = d;
        do {
            if (st_is_boundary(m, x)) bnd++; else real++;
            x = st_beta1(m, x, l);
        } while (x != d);
        if (bnd && real == 1) return ST_SHARP_INFINITE;
    }
    return s;
}

/* Sum and count of the semi-sharp edges (0 < s < infinite) around the vertex
 * of d at level l: what Chaikin's rule averages over. */
static void semi_sharp_around(const st_subdiv_view *sv, uint32_t d, unsigned l, float *sum, unsigned *count)
{
    const st_map *m = sv->map;
    uint32_t x = d;
    *sum = 0;
    *count = 0;
    do {
        float s = st_crease_edge_sharpness(sv, x, l);
        if (s > 0 && s < ST_SHARP_INFINITE) { *sum += s; (*count)++; }
        x = st_beta1(m, x, l);
    } while (x != d);
}

/* Chaikin's rule for one child edge (Sdc::Crease::SubdivideEdgeSharpnessesAroundVertex,
 * CREASE_CHAIKIN): 3/4 of the parent sharpness plus 1/4 of the mean of the
 * other semi-sharp edges at the vertex, less one; alone at its vertex, the
 * uniform decay.  Float arithmetic, as OpenSubdiv's. */
static float chaikin_child(float s, float sum, unsigned count)
{
    if (s <= 0) return 0;
    if (s >= ST_SHARP_INFINITE) return ST_SHARP_INFINITE;
    if (count < 2) return st_crease_decay(s);
    float others = (sum - s) / (float)(count - 1);
    float c = (0.75f * s + 0.25f * others) - 1.0f;
    return c > 0 ? c : 0;
}

float st_crease_child_edge_sharpness(const st_subdiv_view *sv, uint32_t d, unsigned l)
{
    const st_map *m = sv->map;
    float s = st_subdiv_edge_sharpness(sv, d, l);
    /* Boundary edges are infinitely sharp in the rules whatever their tag:
     * their tag decays as it is. */
    if (sv->opts.crease_method != ST_CREASE_CHAIKIN || st_is_boundary(m, d) || st_is_boundary(m, st_beta0(m, d, l)))
        return st_crease_decay(s);
    float sum;
    unsigned count;
    semi_sharp_around(sv, d, l, &sum, &count);
    return chaikin_child(s, sum, count);
}

enum rule { RULE_SMOOTH, RULE_DART, RULE_CREASE, RULE_CORNER };

static enum rule vertex_rule(float vs, unsigned sharp_edges)
{
    if (vs > 0) return RULE_CORNER;
    if (sharp_edges > 2) return RULE_CORNER;
    if (sharp_edges == 2) return RULE_CREASE;
    return sharp_edges ? RULE_DART : RULE_SMOOTH;
}

static void rule_mask(const st_subdiv_view *sv, unsigned l, uint32_t d, enum rule r, const uint32_t crease_end[2],
                      st_vertex_mask_fn smooth, st_stencil_buf *out)
{
    uint32_t v = st_vert(sv->map, d, l);
    if (r == RULE_CORNER) st_stencil_buf_add(out, v, 1.0);
    else if (r == RULE_CREASE) {
        st_stencil_buf_add(out, v, 0.75);
        st_stencil_buf_add(out, crease_end[0], 0.125);
        st_stencil_buf_add(out, crease_end[1], 0.125);
    } else smooth(sv, l, d, out);
}

void st_crease_vertex_point(const st_subdiv_view *sv, unsigned l, uint32_t d, st_vertex_mask_fn smooth,
                            st_stencil_buf *out, st_stencil_buf *tmp)
{
    const st_map *m = sv->map;
    float vs = st_crease_vertex_sharpness(sv, d, l), cvs = st_crease_decay(vs);
    unsigned sharp = 0, csharp = 0, transitions = 0;
    float tsum = 0; /* OpenSubdiv computes the blend weight in float */
    uint32_t ends[2] = { 0, 0 }, cends[2] = { 0, 0 }; /* crease ends for the parent and the child rule */
    uint32_t x = d;
    int chaikin = sv->opts.crease_method == ST_CREASE_CHAIKIN;
    float semi_sum = 0;
    unsigned semi_count = 0;
    if (chaikin) semi_sharp_around(sv, d, l, &semi_sum, &semi_count);
    if (vs > 0 && cvs <= 0) { transitions++; tsum += vs; }
    do {
        float s = st_crease_edge_sharpness(sv, x, l);
        if (s > 0) {
            uint32_t end = st_vert(m, st_beta0(m, x, l), l);
            if (sharp < 2) ends[sharp] = end;
            sharp++;
            float child = chaikin ? chaikin_child(s, semi_sum, semi_count) : st_crease_decay(s);
            if (child > 0) { if (csharp < 2) cends[csharp] = end; csharp++; }
            else { transitions++; tsum += s; }
        }
        x = st_beta1(m, x, l);
    } while (x != d);
    enum rule pr = vertex_rule(vs, sharp), cr = vertex_rule(cvs, csharp);
    st_stencil_buf_clear(out);
    if (pr == RULE_SMOOTH || pr == RULE_DART || pr == cr || transitions == 0) {
        rule_mask(sv, l, d, pr, ends, smooth, out);
        return;
    }
    float wf = tsum / (float)transitions;
    double w = wf > 1.0f ? 1.0 : wf;
    st_stencil_buf_clear(tmp);
    rule_mask(sv, l, d, pr, ends, smooth, tmp);
    st_stencil_buf_add_scaled(out, tmp, w);
    st_stencil_buf_clear(tmp);
    rule_mask(sv, l, d, cr, cends, smooth, tmp);
    st_stencil_buf_add_scaled(out, tmp, 1 - w);
}

void st_crease_edge_point(const st_subdiv_view *sv, unsigned l, uint32_t d, st_edge_mask_fn smooth,
                          st_stencil_buf *out, st_stencil_buf *tmp)
{
    const st_map *m = sv->map;
    float s = st_crease_edge_sharpness(sv, d, l);
    uint32_t a = st_vert(m, d, l), b = st_vert(m, st_beta0(m, d, l), l);
    st_stencil_buf_clear(out);
    if (s <= 0) { smooth(sv, l, d, out); return; }
    double w = st_crease_decay(s) > 0 || s >= 1 ? 1.0 : s;
    if (sv->opts.crease_method == ST_CREASE_CHAIKIN && s < ST_SHARP_INFINITE) {
        /* The child rule is a crease only when both child edges stay sharp
         * (Vtr::Refinement::reclassifySemisharpVertices); otherwise the
         * masks blend by the parent sharpness, unclamped, as
         * Sdc::Scheme::ComputeEdgeVertexMask does. */
        int both = st_crease_child_edge_sharpness(sv, d, l) > 0 &&
                   st_crease_child_edge_sharpness(sv, st_beta0(m, d, l), l) > 0;
        w = both ? 1.0 : s;
    }
    st_stencil_buf_add(out, a, 0.5 * w);
    st_stencil_buf_add(out, b, 0.5 * w);
    if (w != 1) {
        st_stencil_buf_clear(tmp);
        smooth(sv, l, d, tmp);
        st_stencil_buf_add_scaled(out, tmp, 1 - w);
    }
}
