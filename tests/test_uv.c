/* Face-varying texture coordinates (UVs): reading (OBJ vt, PLY u v),
 * repair keeping them parallel to the faces, writing, and their subdivision
 * at every level of a hierarchy (core/fvar/fvar.h). */
#include "testlib.h"

#include "core/io/mesh.h"
#include "core/io/mesh_internal.h"
#include "core/multires/hier.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

static int parse(const char *text, st_mesh *m, st_error *err)
{
    st_mesh_init(m);
    int rc = st_mesh_parse_obj("uv.obj", text, strlen(text), m, err);
    if (!rc) rc = st_mesh_repair("uv.obj", m, NULL, err);
    return rc;
}

/* Two quads sharing an edge, with a seam along it (indices 2,3 vs 5,6). */
static const char *seam_obj =
    "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 2 0 0\nv 2 1 0\n"
    "vt 0 0\nvt 0.5 0\nvt 0.5 1\nvt 0 1\nvt 0.6 0\nvt 0.6 1\nvt 1 0\nvt 1 1\n"
    "f 1/1 2/2/1 3/3 4/4\n"
    "f 2/5 5/7 6/8 3/6\n";

static void test_obj_read(void)
{
    st_mesh m;
    st_error err = {0};
    CHECKF(parse(seam_obj, &m, &err) == 0, "%s", err.msg);
    CHECK(m.nuvs == 8 && m.uv && m.face_uv);
    CHECK(m.uv[2] == 0.5 && m.uv[3] == 0);
    static const uint32_t want[8] = { 0, 1, 2, 3, 4, 6, 7, 5 };
    CHECK(m.face_uv && memcmp(m.face_uv, want, sizeof want) == 0);
    st_mesh_free(&m);
    /* Negative (relative) t indices and `vt u` (v = 0). */
    CHECKF(parse("v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0.25\nvt 1 0\nvt 0 1\nf 1/-3 2/-2 3/-1\n", &m, &err) == 0, "%s", err.msg);
    CHECK(m.nuvs == 3 && m.face_uv && m.face_uv[0] == 0 && m.face_uv[2] == 2 && m.uv[0] == 0.25 && m.uv[1] == 0);
    st_mesh_free(&m);
    /* No vt at all: no channel, unchanged memory. */
    CHECK(parse("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n", &m, &err) == 0);
    CHECK(m.nuvs == 0 && !m.uv && !m.face_uv);
    st_mesh_free(&m);
    /* A face without t next to one with: the channel is dropped. */
    CHECK(parse("v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nvt 0 0\nvt 1 0\nvt 0 1\nf 1/1 2/2 3/3\nf 2 4 3\n", &m, &err) == 0);
    CHECK(m.nuvs == 0 && !m.uv && !m.face_uv);
    st_mesh_free(&m);
}

static void test_obj_bad(void)
{
    st_mesh m;
    st_error err = {0};
    CHECK(parse("v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nf 1/1 2/2 3/1\n", &m, &err) != 0);
    CHECKF(strstr(err.msg, "uv.obj:5:") && strstr(err.msg, "texture coordinate 2"), "%s", err.msg);
    CHECK(parse("v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nf 1/0 2/1 3/1\n", &m, &err) != 0);
    CHECKF(strstr(err.msg, "uv.obj:5:") && strstr(err.msg, "index 0"), "%s", err.msg);
    CHECK(parse("v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nf 1/-2 2/1 3/1\n", &m, &err) != 0);
    CHECKF(strstr(err.msg, "uv.obj:5:") && strstr(err.msg, "relative"), "%s", err.msg);
    CHECK(parse("v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nf 1/1 2 3/1\n", &m, &err) != 0);
    CHECKF(strstr(err.msg, "uv.obj:5:") && strstr(err.msg, "2 of its 3"), "%s", err.msg);
    CHECK(parse("v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 x\nf 1/1 2/1 3/1\n", &m, &err) != 0);
    CHECKF(strstr(err.msg, "uv.obj:4:") && strstr(err.msg, "bad texture coordinate"), "%s", err.msg);
    CHECK(parse("v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 inf\nf 1/1 2/1 3/1\n", &m, &err) != 0);
    CHECKF(strstr(err.msg, "uv.obj:4:"), "%s", err.msg);
    CHECK(parse("v 0 0 0\nv 1 0 0\nv 0 1 0\nvt\nf 1/1 2/1 3/1\n", &m, &err) != 0);
    CHECKF(strstr(err.msg, "uv.obj:4:"), "%s", err.msg);
}

/* Repair flips a face: its UV indices turn with its vertices. */
static void test_repair_flip(void)
{
    st_mesh m;
    st_error err = {0};
    /* Second face wound the wrong way. */
    CHECKF(parse("v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 2 0 0\nv 2 1 0\n"
                 "vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\nvt 2 0\nvt 2 1\n"
                 "f 1/1 2/2 3/3 4/4\nf 2/2 3/3 6/6 5/5\n", &m, &err) == 0, "%s", err.msg);
    CHECK(m.face_uv != NULL);
    for (uint32_t c = 0; m.face_uv && c < m.face_off[m.nfaces]; c++)
        CHECKF(m.face_uv[c] == m.face_idx[c], "corner %u: vertex %u uv %u", c, m.face_idx[c], m.face_uv[c]);
    CHECK(st_mesh_check("uv.obj", &m, &err) == 0);
    /* check refuses an index out of range */
    m.face_uv[0] = 99;
    CHECK(st_mesh_check("uv.obj", &m, &err) != 0);
    st_mesh_free(&m);
}

static void test_obj_roundtrip(void)
{
    st_mesh m, b;
    st_error err = {0};
    CHECK(parse(seam_obj, &m, &err) == 0);
    char path[512];
    snprintf(path, sizeof path, "%s/uv_roundtrip.obj", STRATA_TMP);
    CHECKF(st_mesh_save_obj(path, &m, &err) == 0, "%s", err.msg);
    st_mesh_init(&b);
    CHECKF(st_mesh_load(path, &b, &err) == 0, "%s", err.msg);
    CHECK(b.nuvs == m.nuvs && b.face_uv && memcmp(b.uv, m.uv, 2 * m.nuvs * sizeof *m.uv) == 0 &&
          memcmp(b.face_uv, m.face_uv, m.face_off[m.nfaces] * sizeof *m.face_uv) == 0);
    st_mesh_free(&b);
    st_mesh_free(&m);
}

static void test_ply_read(void)
{
    static const char *names[3][2] = {{"u", "v"}, {"s", "t"}, {"texture_u", "texture_v"}};
    for (int n = 0; n < 3; n++) {
        char text[1024];
        snprintf(text, sizeof text, "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
                 "property float z\nproperty float %s\nproperty float %s\nelement face 1\n"
                 "property list uchar int vertex_indices\nend_header\n"
                 "0 0 0 0.1 0.2\n1 0 0 0.3 0.4\n0 1 0 0.5 0.6\n3 0 1 2\n", names[n][0], names[n][1]);
        st_mesh m;
        st_error err = {0};
        st_mesh_init(&m);
        CHECKF(st_mesh_parse_ply("uv.ply", text, strlen(text), &m, &err) == 0, "%s", err.msg);
        CHECK(m.nuvs == 3 && m.face_uv && m.face_uv[1] == 1 && fabs(m.uv[2] - 0.3) < 1e-7 && fabs(m.uv[5] - 0.6) < 1e-7);
        st_mesh_free(&m);
    }
}

int main(void)
{
    test_ply_read();
    test_obj_read();
    test_obj_bad();
    test_repair_flip();
    test_obj_roundtrip();
    return TEST_END();
}
