// pg_export_encode.cpp - PNG/JPEG encoding into memory with OpenImageIO; see
// pg_export_encode.h. OIIO's IOVecOutput proxy collects the file's bytes in a
// vector, so no temporary file is needed. Floats are quantised here (clamp to 0..1,
// round to nearest) so every encoder sees the same integers.
#include "pg_export_encode.h"
#include "pg_quantise.h"
#include "planetgen/pg_image.h"

#include <OpenImageIO/filesystem.h>
#include <OpenImageIO/imageio.h>

#include <cmath>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <string>
#include <vector>

using namespace OIIO;

template <typename T>
static void quantise(const float *src, int w, int h, int ch, bool bottom_up, double maxv,
                     std::vector<T> &out) {
    out.resize((size_t)w * h * ch);
    size_t row = (size_t)w * ch;
    for (int y = 0; y < h; y++) {
        const float *s = src + (size_t)(bottom_up ? h - 1 - y : y) * row;
        T *d = out.data() + (size_t)y * row;
        for (size_t i = 0; i < row; i++) {
            float v = s[i];
            v = v > 0.0f ? (v < 1.0f ? v : 1.0f) : 0.0f; // NaN -> 0
            d[i] = (T)pg_round_half_up(v * maxv);
        }
    }
}

static pg_status encode_fail(pg_error *err, const char *what, const char *fmt, std::string msg) {
    for (char &c : msg)
        if (c == '\n' || c == '\r') c = ' ';
    return pg_error_set(err, PG_ERR_RUNTIME, "%s: %s encoding failed: %s", what, fmt, msg.c_str());
}

extern "C" pg_status pg_export_encode(const float *data, int width, int height, int channels,
                                      int bits, bool bottom_up, pg_export_codec codec, int quality,
                                      const char *what, uint8_t **bytes, size_t *size,
                                      pg_error *err) {
    *bytes = nullptr;
    *size = 0;
    const bool jpeg = codec == PG_EXPORT_CODEC_JPEG;
    const char *fmt = jpeg ? "jpeg" : "png";
    if (jpeg) bits = 8;
    if (bits != 8 && bits != 16)
        return pg_error_set(err, PG_ERR_BADINPUT, "%s: %d bits per sample unsupported", what, bits);
    std::vector<unsigned char> out;
    try {
        std::vector<uint8_t> q8;
        std::vector<uint16_t> q16;
        const void *pixels;
        TypeDesc type = bits == 16 ? TypeDesc::UINT16 : TypeDesc::UINT8;
        if (bits == 16) {
            quantise(data, width, height, channels, bottom_up, 65535.0, q16);
            pixels = q16.data();
        } else {
            quantise(data, width, height, channels, bottom_up, 255.0, q8);
            pixels = q8.data();
        }
        Filesystem::IOVecOutput vec(out);
        std::string name = std::string("mem.") + fmt;
        auto img = ImageOutput::create(name);
        if (!img) return encode_fail(err, what, fmt, OIIO::geterror());
        ImageSpec spec(width, height, channels, type);
        if (jpeg)
            spec.attribute("Compression", "jpeg:" + std::to_string(quality));
        else {
            spec.attribute("png:compressionLevel", PG_PNG_COMPRESSION_LEVEL);
            spec.attribute("compression", PG_PNG_STRATEGY);
            spec.attribute("png:filter", PG_PNG_FILTER);
        }
        if (!img->set_ioproxy(&vec)) return encode_fail(err, what, fmt, img->geterror());
        // No software/date metadata: identical planets give identical files.
        if (!img->open(name, spec)) return encode_fail(err, what, fmt, img->geterror());
        bool ok = img->write_image(type, pixels);
        ok = img->close() && ok;
        if (!ok) return encode_fail(err, what, fmt, img->geterror());
    } catch (const std::exception &e) {
        return pg_error_set(err, PG_ERR_NOMEM, "%s: %s encoding: %s", what, fmt, e.what());
    }
    *bytes = (uint8_t *)std::malloc(out.size() ? out.size() : 1);
    if (!*bytes) return pg_error_set(err, PG_ERR_NOMEM, "%s: out of memory", what);
    std::memcpy(*bytes, out.data(), out.size());
    *size = out.size();
    return PG_OK;
}
