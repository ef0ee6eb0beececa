/* 32-bit float OpenEXR files through tinyexr (Debian libtinyexr-dev), behind
 * a C API: app/exr_io.cc is its one C++ translation unit. */
#ifndef ST_EXR_IO_H
#define ST_EXR_IO_H

#ifdef __cplusplus
extern "C" {
#endif

/* Writes w × h pixels of `channels` (1 or 3) floats, row 0 first; returns
 * 0, or -1 with a message of at most msg_size bytes in msg. */
int st_exr_write(const char *path, const float *pixels, int w, int h, int channels, char *msg, unsigned msg_size);

#ifdef __cplusplus
}
#endif

#endif
