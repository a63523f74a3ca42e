// pg_oiio.cpp - the OpenImageIO adapter behind pg_image.h (reading all formats,
// writing PNG). C++ stays inside this file: the header is plain C.
//
// Reads first check the path with stat() so that "missing", "directory" and
// "empty" get precise messages, then open the file and check its size against the
// pixel limit BEFORE any pixel memory is allocated. OpenImageIO reports truncated
// data as an error from read_image (or as a pending error message): both count.
#include "pg_huge.h"
#include "pg_quantise.h"
#include "planetgen/pg_image.h"

#include <OpenImageIO/filesystem.h>
#include <OpenImageIO/imageio.h>

#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <string>
#include <sys/stat.h>
#include <vector>

using namespace OIIO;

static pg_status check_path(const char *path, pg_error *err) {
    struct stat st;
    if (stat(path, &st) != 0)
        return pg_error_set(err, PG_ERR_BADINPUT, "%s: %s", path, std::strerror(errno));
    if (S_ISDIR(st.st_mode))
        return pg_error_set(err, PG_ERR_BADINPUT, "%s: is a directory, not an image", path);
    if (st.st_size == 0) return pg_error_set(err, PG_ERR_BADINPUT, "%s: empty file", path);
    return PG_OK;
}

static std::string one_line(std::string s) {
    for (char &c : s)
        if (c == '\n' || c == '\r') c = ' ';
    while (!s.empty() && s.back() == ' ')
        s.pop_back();
    if (s.size() > 200) s = s.substr(0, 200) + "...";
    return s;
}

static bool map_type(TypeDesc t, pg_image_sample_type *st, float *scale) {
    switch (t.basetype) {
    case TypeDesc::UINT8:
        *st = PG_SAMPLE_UINT8;
        *scale = 1.0f / 255.0f;
        return true;
    case TypeDesc::INT8:
        *st = PG_SAMPLE_INT8;
        *scale = 1.0f / 127.0f;
        return true;
    case TypeDesc::UINT16:
        *st = PG_SAMPLE_UINT16;
        *scale = 1.0f / 65535.0f;
        return true;
    case TypeDesc::INT16:
        *st = PG_SAMPLE_INT16;
        *scale = 1.0f / 32767.0f;
        return true;
    case TypeDesc::UINT32:
        *st = PG_SAMPLE_UINT32;
        *scale = 1.0f / 4294967295.0f;
        return true;
    case TypeDesc::INT32:
        *st = PG_SAMPLE_INT32;
        *scale = 1.0f / 2147483647.0f;
        return true;
    case TypeDesc::HALF:
        *st = PG_SAMPLE_HALF;
        *scale = 1.0f;
        return true;
    case TypeDesc::FLOAT:
        *st = PG_SAMPLE_FLOAT;
        *scale = 1.0f;
        return true;
    case TypeDesc::DOUBLE:
        *st = PG_SAMPLE_DOUBLE;
        *scale = 1.0f;
        return true;
    default:
        return false;
    }
}

// Convert raw samples to float without normalising, so integer heights keep units.
template <typename T> static void widen(const void *src, float *dst, size_t n) {
    const T *s = static_cast<const T *>(src);
    for (size_t i = 0; i < n; i++)
        dst[i] = static_cast<float>(s[i]);
}

static void widen_any(TypeDesc t, const void *src, float *dst, size_t n) {
    switch (t.basetype) {
    case TypeDesc::UINT8:
        widen<uint8_t>(src, dst, n);
        break;
    case TypeDesc::INT8:
        widen<int8_t>(src, dst, n);
        break;
    case TypeDesc::UINT16:
        widen<uint16_t>(src, dst, n);
        break;
    case TypeDesc::INT16:
        widen<int16_t>(src, dst, n);
        break;
    case TypeDesc::UINT32:
        widen<uint32_t>(src, dst, n);
        break;
    case TypeDesc::INT32:
        widen<int32_t>(src, dst, n);
        break;
    case TypeDesc::FLOAT:
        std::memcpy(dst, src, n * sizeof(float));
        break;
    case TypeDesc::DOUBLE:
        widen<double>(src, dst, n);
        break;
    default:
        break;
    }
}

// The decoder is chosen by the file's magic bytes, not its name, and only among
// the formats planetgen supports. Letting OpenImageIO try every reader it has on an
// unknown file is slow (dozens of plugins) and exposes decoders nobody asked for.
static const char *sniff_format(const char *path) {
    unsigned char b[12] = {0};
    FILE *f = std::fopen(path, "rb");
    if (!f) return nullptr;
    size_t n = std::fread(b, 1, sizeof b, f);
    std::fclose(f);
    if (n >= 8 && !std::memcmp(b, "\x89PNG\r\n\x1a\n", 8)) return "png";
    if (n >= 3 && b[0] == 0xff && b[1] == 0xd8 && b[2] == 0xff) return "jpeg";
    if (n >= 4 && (!std::memcmp(b, "II*\0", 4) || !std::memcmp(b, "MM\0*", 4) ||
                   !std::memcmp(b, "II+\0", 4) || !std::memcmp(b, "MM\0+", 4)))
        return "tiff";
    if (n >= 4 && b[0] == 0x76 && b[1] == 0x2f && b[2] == 0x31 && b[3] == 0x01) return "openexr";
    if (n >= 2 && b[0] == 'B' && b[1] == 'M') return "bmp";
    if (n >= 2 && b[0] == '#' && b[1] == '?') return "hdr";
    if (n >= 12 && !std::memcmp(b, "RIFF", 4) && !std::memcmp(b + 8, "WEBP", 4)) return "webp";
    return nullptr;
}

static pg_status open_input(const char *path, std::unique_ptr<ImageInput> &in, pg_error *err) {
    pg_status st = check_path(path, err);
    if (st == PG_OK) st = pg_image_png_check(path, err);
    if (st == PG_OK) st = pg_image_jpeg_check(path, err);
    if (st == PG_OK) st = pg_image_exr_check(path, err);
    if (st != PG_OK) return st;
    const char *fmt = sniff_format(path);
    if (!fmt)
        return pg_error_set(err, PG_ERR_BADINPUT,
                            "%s: not a readable image (supported: JPEG, PNG, TIFF, OpenEXR, BMP, "
                            "HDR, WebP)",
                            path);
    // Alpha is ignored, never applied: ask for the file's unassociated colours,
    // or a PNG with alpha would come back premultiplied.
    ImageSpec config;
    config.attribute("oiio:UnassociatedAlpha", 1);
    in = ImageInput::create(fmt);
    ImageSpec opened;
    if (in && !in->open(path, opened, config)) {
        std::string e = one_line(in->geterror());
        return pg_error_set(err, PG_ERR_BADINPUT, "%s: not a readable image (%s)", path,
                            e.empty() ? "cannot open" : e.c_str());
    }
    if (!in) {
        std::string e = one_line(OIIO::geterror());
        return pg_error_set(err, PG_ERR_BADINPUT, "%s: not a readable image (%s)", path,
                            e.empty() ? "unknown format" : e.c_str());
    }
    return PG_OK;
}

extern "C" pg_status pg_image_probe(const char *path, int *width, int *height, int *channels,
                                    pg_error *err) {
    std::unique_ptr<ImageInput> in;
    pg_status st = open_input(path, in, err);
    if (st != PG_OK) return st;
    const ImageSpec &spec = in->spec();
    *width = spec.width;
    *height = spec.height;
    *channels = spec.nchannels;
    in->close();
    return PG_OK;
}

extern "C" pg_status pg_image_read(const char *path, uint64_t max_pixels, pg_image *out,
                                   pg_error *err) {
    std::memset(out, 0, sizeof *out);
    std::unique_ptr<ImageInput> in;
    pg_status st = open_input(path, in, err);
    if (st != PG_OK) return st;
    const ImageSpec &spec = in->spec();
    if (max_pixels == 0) max_pixels = PG_IMAGE_DEFAULT_MAX_PIXELS;
    uint64_t npix = (uint64_t)spec.width * (uint64_t)spec.height;
    if (spec.width <= 0 || spec.height <= 0 || spec.nchannels <= 0 || spec.depth > 1)
        return pg_error_set(err, PG_ERR_BADINPUT, "%s: unsupported image geometry %dx%dx%d", path,
                            spec.width, spec.height, spec.depth);
    if (npix > max_pixels)
        return pg_error_set(err, PG_ERR_BADINPUT,
                            "%s: %dx%d is %.0f Mpx, above the limit of %.0f Mpx", path, spec.width,
                            spec.height, npix / 1e6, max_pixels / 1e6);
    pg_image_sample_type stype;
    float scale;
    if (!map_type(spec.format, &stype, &scale))
        return pg_error_set(err, PG_ERR_BADINPUT, "%s: unsupported sample type %s", path,
                            spec.format.c_str());
    size_t n = (size_t)npix * (size_t)spec.nchannels;
    std::vector<unsigned char> raw;
    float *data = static_cast<float *>(pg_huge_malloc(n * sizeof(float)));
    try {
        if (!spec.format.is_floating_point()) raw.resize(n * spec.format.size());
    } catch (...) {
        std::free(data);
        data = nullptr;
    }
    if (!data)
        return pg_error_set(err, PG_ERR_NOMEM, "%s: cannot allocate %.0f MB for pixels", path,
                            n * 4.0 / 1e6);
    // Floating-point files are read straight as float (OIIO does not normalise
    // floats); integer files natively, then widened without normalising.
    bool is_float = spec.format.is_floating_point();
    if (is_float) raw.clear();
    bool ok = is_float ? in->read_image(0, 0, 0, spec.nchannels, TypeDesc::FLOAT, data)
                       : in->read_image(0, 0, 0, spec.nchannels, spec.format, raw.data());
    std::string e = one_line(in->geterror());
    in->close();
    if (!ok || !e.empty()) {
        std::free(data);
        return pg_error_set(err, PG_ERR_BADINPUT, "%s: corrupt or truncated image (%s)", path,
                            e.empty() ? "read failed" : e.c_str());
    }
    if (!is_float) widen_any(spec.format, raw.data(), data, n);
    out->width = spec.width;
    out->height = spec.height;
    out->channels = spec.nchannels;
    out->data = data;
    out->src_type = stype;
    out->unit_scale = scale;
    std::snprintf(out->format_name, sizeof out->format_name, "%s", in->format_name());
    return PG_OK;
}

template <typename T> static std::vector<T> quantise(const pg_image *img, double maxv) {
    size_t n = (size_t)img->width * img->height * img->channels;
    std::vector<T> q(n);
    for (size_t i = 0; i < n; i++) {
        double v = img->data[i];
        v = std::isfinite(v) ? v : 0.0;
        v = v < 0 ? 0 : (v > 1 ? 1 : v);
        q[i] = static_cast<T>(pg_round_half_up(v * maxv));
    }
    return q;
}

// The spec of every PNG planetgen writes (pg_image.h: PG_PNG_*).
static ImageSpec png_spec(const pg_image *img, TypeDesc fmt) {
    ImageSpec spec(img->width, img->height, img->channels, fmt);
    spec.attribute("oiio:UnassociatedAlpha", 1); // our colours are never premultiplied
    spec.attribute("png:compressionLevel", PG_PNG_COMPRESSION_LEVEL);
    spec.attribute("compression", PG_PNG_STRATEGY);
    spec.attribute("png:filter", PG_PNG_FILTER);
    return spec;
}

// The image's samples, quantised to `bits`, through an opened output; then close it.
static bool png_pixels(ImageOutput *out, const pg_image *img, int bits) {
    bool ok;
    if (bits == 8) {
        std::vector<uint8_t> q = quantise<uint8_t>(img, 255.0);
        ok = out->write_image(TypeDesc::UINT8, q.data());
    } else {
        std::vector<uint16_t> q = quantise<uint16_t>(img, 65535.0);
        ok = out->write_image(TypeDesc::UINT16, q.data());
    }
    return out->close() && ok;
}

extern "C" pg_status pg_image_encode_png(const pg_image *img, int bits, uint8_t **bytes,
                                         size_t *size, pg_error *err) {
    *bytes = nullptr;
    *size = 0;
    if (bits != 8 && bits != 16)
        return pg_error_set(err, PG_ERR_BADINPUT, "PNG bit depth %d not 8 or 16", bits);
    std::vector<unsigned char> buf;
    try {
        Filesystem::IOVecOutput vec(buf);
        auto out = ImageOutput::create("mem.png");
        ImageSpec spec = png_spec(img, bits == 8 ? TypeDesc::UINT8 : TypeDesc::UINT16);
        if (!out || !out->set_ioproxy(&vec) || !out->open("mem.png", spec))
            return pg_error_set(err, PG_ERR_RUNTIME, "PNG encoding failed (%s)",
                                one_line(out ? out->geterror() : OIIO::geterror()).c_str());
        if (!png_pixels(out.get(), img, bits))
            return pg_error_set(err, PG_ERR_RUNTIME, "PNG encoding failed (%s)",
                                one_line(out->geterror()).c_str());
    } catch (const std::exception &e) {
        return pg_error_set(err, PG_ERR_NOMEM, "PNG encoding: %s", e.what());
    }
    *bytes = (uint8_t *)std::malloc(buf.size() ? buf.size() : 1);
    if (!*bytes) return pg_error_set(err, PG_ERR_NOMEM, "PNG encoding: out of memory");
    std::memcpy(*bytes, buf.data(), buf.size());
    *size = buf.size();
    return PG_OK;
}

extern "C" pg_status pg_image_write_png(const char *path, const pg_image *img, int bits,
                                        pg_error *err) {
    if (bits != 8 && bits != 16)
        return pg_error_set(err, PG_ERR_BADINPUT, "%s: PNG bit depth %d not 8 or 16", path, bits);
    ImageSpec spec = png_spec(img, bits == 8 ? TypeDesc::UINT8 : TypeDesc::UINT16);
    auto out = ImageOutput::create("png");
    if (!out || !out->open(path, spec))
        return pg_error_set(err, PG_ERR_IO, "%s: cannot write (%s)", path,
                            one_line(out ? out->geterror() : OIIO::geterror()).c_str());
    if (!png_pixels(out.get(), img, bits))
        return pg_error_set(err, PG_ERR_IO, "%s: write failed (%s)", path,
                            one_line(out->geterror()).c_str());
    // libpng inside OpenImageIO does not report a short write (full disk, file-size
    // limit): the file would silently end early. Read its chunk structure back.
    pg_error chk = {PG_OK, {0}};
    if (pg_image_png_check(path, &chk) != PG_OK)
        return pg_error_set(err, PG_ERR_IO, "%s: write failed, file is incomplete (disk full?)",
                            path);
    return PG_OK;
}
