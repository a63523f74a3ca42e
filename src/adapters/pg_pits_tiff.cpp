// pg_pits_tiff.cpp - the OpenImageIO adapter behind pg_pits_tiff.h: float32 TIFF
// output that keeps the input's GeoTIFF georeferencing attributes. C++ stays here.
#include "pg_pits_tiff.h"

#include <OpenImageIO/imageio.h>

#include <string>

using namespace OIIO;

// Copy every "GeoTIFF:" attribute of `like` (if it opens) into spec.
static void copy_georef(const char *like, ImageSpec &spec) {
    if (!like) return;
    auto in = ImageInput::open(like);
    if (!in) {
        (void)OIIO::geterror();
        return;
    }
    for (const ParamValue &p : in->spec().extra_attribs) {
        std::string name = p.name().string();
        if (name.rfind("GeoTIFF:", 0) == 0) spec.attribute(name, p.type(), p.data());
    }
    in->close();
}

extern "C" pg_status pg_pits_write_tiff(const char *path, const float *data, int w, int h,
                                        const char *like, pg_error *err) {
    ImageSpec spec(w, h, 1, TypeDesc::FLOAT);
    spec.attribute("compression", "zip");
    copy_georef(like, spec);
    auto out = ImageOutput::create("tiff");
    if (!out) return pg_error_set(err, PG_ERR_RUNTIME, "%s: no TIFF writer", path);
    if (!out->open(path, spec))
        return pg_error_set(err, PG_ERR_IO, "%s: cannot write (%s)", path, out->geterror().c_str());
    bool ok = out->write_image(TypeDesc::FLOAT, data);
    ok = out->close() && ok;
    if (!ok) return pg_error_set(err, PG_ERR_IO, "%s: write failed (disk full?)", path);
    return PG_OK;
}
