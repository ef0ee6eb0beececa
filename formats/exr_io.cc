// OpenEXR writing through tinyexr (formats/exr_io.h).  The shared library
// carries tinyexr's implementation: TINYEXR_IMPLEMENTATION is not defined.
// SaveEXR would name a single channel "A" (alpha); a displacement map is
// luminance, so the header is filled here: "Y", or "B" "G" "R" (OpenEXR
// lists channels alphabetically), 32-bit float, ZIP compression.
#include "exr_io.h"

#include <tinyexr.h>

#include <cstdio>
#include <cstring>
#include <vector>

extern "C" int st_exr_encode(const float *pixels, int w, int h, int channels, unsigned char **out, size_t *size, char *msg,
                             unsigned msg_size)
{
    if (channels != 1 && channels != 3) {
        std::snprintf(msg, msg_size, "an EXR map has 1 or 3 channels, not %d", channels);
        return -1;
    }
    size_t n = (size_t)w * (size_t)h;
    std::vector<std::vector<float>> planes((size_t)channels, std::vector<float>(n));
    for (size_t i = 0; i < n; i++)
        for (int c = 0; c < channels; c++) planes[(size_t)c][i] = pixels[i * (size_t)channels + (size_t)c];
    // Channel order in the file: B, G, R for three channels (alphabetical).
    static const char *const names3[3] = { "B", "G", "R" };
    std::vector<unsigned char *> ptrs((size_t)channels);
    std::vector<EXRChannelInfo> info((size_t)channels);
    std::vector<int> types((size_t)channels, TINYEXR_PIXELTYPE_FLOAT);
    for (int c = 0; c < channels; c++) {
        int src = channels == 3 ? 2 - c : 0;
        ptrs[(size_t)c] = reinterpret_cast<unsigned char *>(planes[(size_t)src].data());
        std::memset(&info[(size_t)c], 0, sizeof info[(size_t)c]);
        std::snprintf(info[(size_t)c].name, sizeof info[(size_t)c].name, "%s", channels == 3 ? names3[c] : "Y");
    }
    EXRImage image;
    InitEXRImage(&image);
    image.num_channels = channels;
    image.images = ptrs.data();
    image.width = w;
    image.height = h;
    EXRHeader header;
    InitEXRHeader(&header);
    header.num_channels = channels;
    header.channels = info.data();
    header.pixel_types = types.data();
    header.requested_pixel_types = types.data();
    header.compression_type = TINYEXR_COMPRESSIONTYPE_ZIP;
    const char *err = nullptr;
    unsigned char *mem = nullptr;
    // tinyexr allocates the result with malloc; 0 bytes is its failure.
    size_t bytes = SaveEXRImageToMemory(&image, &header, &mem, &err);
    if (bytes > 0 && mem) {
        *out = mem;
        *size = bytes;
        return 0;
    }
    std::snprintf(msg, msg_size, "%s", err ? err : "tinyexr could not encode the image");
    if (err) FreeEXRErrorMessage(err);
    return -1;
}
