/* 32-bit float OpenEXR files through tinyexr (Debian libtinyexr-dev), behind
 * a C API: formats/exr_io.cc is its one C++ translation unit. */
#ifndef ST_EXR_IO_H
#define ST_EXR_IO_H

#ifdef __cplusplus
extern "C" {
#endif

#include <stddef.h>

/* Encodes w × h pixels of `channels` (1 or 3) floats, row 0 first, as an
 * EXR file in memory (*out, malloc'ed: the caller frees; *size bytes), so
 * that the caller writes it where and how it writes every file (atomically,
 * core/io/atomic_file.h).  Returns 0, or -1 with a message of at most
 * msg_size bytes in msg. */
int st_exr_encode(const float *pixels, int w, int h, int channels, unsigned char **out, size_t *size, char *msg,
                  unsigned msg_size);

#ifdef __cplusplus
}
#endif

#endif
