/* libFuzzer target for glTF external buffers read from files
 * (formats/gltf_io.h st_gltf_load): the fuzzed bytes are written as
 * g/fuzz.gltf into a private temporary folder R next to a fixed
 * tetrahedron g/tet.bin (and g/sub/tet.bin), and loaded.  Beside them lie
 * what a hostile URI could reach for: R/outside.bin, a symlink g/link.bin
 * to it, a symlink g/in.bin to tet.bin, a FIFO g/fifo and a folder g/dir.
 * Every open() the reader makes while loading is checked (the target links
 * with -Wl,--wrap=open): a file whose real path is not inside R/g aborts,
 * as does a FIFO being waited on (libFuzzer's -timeout).  A refusal gives
 * one line naming the file; a load passes st_mesh_check.
 *   fuzz_gltf_ext -max_total_time=60 /tmp/corpus_gltf_ext   (a copy of
 *   tests/fuzz/corpus/gltf_ext: the fuzzer writes into its corpus folder) */
#include "formats/gltf_io.h"

#include <fcntl.h>
#include <limits.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

int LLVMFuzzerInitialize(int *argc, char ***argv);
int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);
int __real_open(const char *path, int flags, ...);
int __wrap_open(const char *path, int flags, ...);

static char root[] = "/tmp/strata-fuzz-gltf.XXXXXX";
static char inside[PATH_MAX + 2]; /* realpath of R/g, with a trailing '/' */
static char gltf[PATH_MAX];
static int checking, opened;

int __wrap_open(const char *path, int flags, ...)
{
    mode_t mode = 0;
    if (flags & O_CREAT) {
        va_list ap;
        va_start(ap, flags);
        mode = (mode_t)va_arg(ap, int);
        va_end(ap);
    }
    if (checking) {
        char real[PATH_MAX];
        if (realpath(path, real) && strncmp(real, inside, strlen(inside))) {
            fprintf(stderr, "the reader opened %s (%s), outside %s\n", path, real, inside);
            abort();
        }
        opened++;
    }
    return __real_open(path, flags, mode);
}

static void put(const char *rel, const void *d, size_t n)
{
    char p[PATH_MAX];
    snprintf(p, sizeof p, "%s/%s", root, rel);
    FILE *f = fopen(p, "wb");
    if (!f || fwrite(d, 1, n, f) != n || fclose(f)) { perror(p); abort(); }
}

static void cleanup(void)
{
    static const char *const files[] = { "g/fuzz.gltf", "g/tet.bin", "g/sub/tet.bin", "g/link.bin", "g/in.bin",
                                         "g/fifo", "outside.bin" };
    static const char *const dirs[] = { "g/sub", "g/dir", "g", "" };
    char p[PATH_MAX];
    for (size_t i = 0; i < sizeof files / sizeof files[0]; i++) {
        snprintf(p, sizeof p, "%s/%s", root, files[i]);
        unlink(p);
    }
    for (size_t i = 0; i < sizeof dirs / sizeof dirs[0]; i++) {
        snprintf(p, sizeof p, "%s/%s", root, dirs[i]);
        rmdir(p);
    }
}

static int load(const uint8_t *data, size_t size, st_mesh *m, st_error *err)
{
    put("g/fuzz.gltf", data, size);
    checking = 1;
    int rc = st_gltf_load(gltf, m, err);
    checking = 0;
    return rc;
}

int LLVMFuzzerInitialize(int *argc, char ***argv)
{
    (void)argc;
    (void)argv;
    if (!mkdtemp(root)) { perror("mkdtemp"); abort(); }
    atexit(cleanup);
    char p[PATH_MAX];
    snprintf(p, sizeof p, "%s/g", root);
    if (mkdir(p, 0700)) abort();
    snprintf(p, sizeof p, "%s/g/sub", root);
    if (mkdir(p, 0700)) abort();
    snprintf(p, sizeof p, "%s/g/dir", root);
    if (mkdir(p, 0700)) abort();
    /* A tetrahedron: 4 float positions (48 bytes), then 12 u16 indices. */
    unsigned char bin[72];
    const float pos[12] = { 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1 };
    const unsigned short idx[12] = { 0, 2, 1, 0, 1, 3, 0, 3, 2, 1, 2, 3 };
    memcpy(bin, pos, 48);
    memcpy(bin + 48, idx, 24);
    put("g/tet.bin", bin, sizeof bin);
    put("g/sub/tet.bin", bin, sizeof bin);
    put("outside.bin", bin, sizeof bin);
    char t[PATH_MAX];
    snprintf(p, sizeof p, "%s/g/link.bin", root);
    snprintf(t, sizeof t, "%s/outside.bin", root);
    if (symlink(t, p)) abort();
    snprintf(p, sizeof p, "%s/g/in.bin", root);
    if (symlink("tet.bin", p)) abort();
    snprintf(p, sizeof p, "%s/g/fifo", root);
    if (mkfifo(p, 0600)) abort();
    snprintf(p, sizeof p, "%s/g", root);
    if (!realpath(p, inside)) abort();
    strcat(inside, "/");
    snprintf(gltf, sizeof gltf, "%s/g/fuzz.gltf", root);
    /* The check must be in effect: a good file is read through open(). */
    static const char good[] =
        "{\"asset\":{\"version\":\"2.0\"},\"buffers\":[{\"uri\":\"tet.bin\",\"byteLength\":72}],"
        "\"bufferViews\":[{\"buffer\":0,\"byteOffset\":0,\"byteLength\":48},{\"buffer\":0,\"byteOffset\":48,\"byteLength\":24}],"
        "\"accessors\":[{\"bufferView\":0,\"componentType\":5126,\"count\":4,\"type\":\"VEC3\",\"min\":[0,0,0],\"max\":[1,1,1]},"
        "{\"bufferView\":1,\"componentType\":5123,\"count\":12,\"type\":\"SCALAR\"}],"
        "\"meshes\":[{\"primitives\":[{\"attributes\":{\"POSITION\":0},\"indices\":1}]}]}";
    st_mesh m;
    st_error err = { 0 };
    st_mesh_init(&m);
    if (load((const uint8_t *)good, sizeof good - 1, &m, &err) || m.nfaces != 4 || !opened) {
        fprintf(stderr, "fuzz_gltf_ext: the fixture does not load through the checked open() (%s)\n", err.msg);
        abort();
    }
    st_mesh_free(&m);
    return 0;
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    if (size > ((size_t)1 << 20)) return 0;
    st_mesh m;
    st_error err = { 0 };
    st_mesh_init(&m);
    m.nverts = 7; /* a marker: a failed load must not touch the output */
    if (load(data, size, &m, &err) != 0) {
        if (m.nverts != 7 || m.pos || m.face_off || strchr(err.msg, '\n') || !strstr(err.msg, "fuzz.gltf")) {
            fprintf(stderr, "bad failure: %s\n", err.msg);
            abort();
        }
        return 0;
    }
    if (st_mesh_check("fuzz.gltf", &m, &err) != 0) {
        fprintf(stderr, "a loaded mesh fails the check: %s\n", err.msg);
        abort();
    }
    st_mesh_free(&m);
    return 0;
}
