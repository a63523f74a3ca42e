// pg_planet_meta.cpp - reads planet.json with nlohmann/json (already required by
// tinygltf), behind the C header pg_planet_meta.h. Every key is checked for
// presence, type and range, because planet directories come from disk and may be
// damaged or hand-edited; the fuzzers feed this reader too.
#include "pg_planet_meta.h"

#include <nlohmann/json.hpp>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <string>

using nlohmann::json;

static bool get_num(const json &j, const char *key, double lo, double hi, double *out) {
    auto it = j.find(key);
    if (it == j.end() || !it->is_number()) return false;
    double v = it->get<double>();
    if (!std::isfinite(v) || v < lo || v > hi) return false;
    *out = v;
    return true;
}

static bool get_str(const json &j, const char *key, char *buf, size_t size) {
    auto it = j.find(key);
    if (it == j.end() || !it->is_string()) return false;
    std::snprintf(buf, size, "%s", it->get<std::string>().c_str());
    return true;
}

// The optional "source" object (the coordinate map, pg_planet.h): a plain file name,
// the exemplar face size (1..8192, the packed coordinates' range) and a projection
// name, checked by the caller against the known projections.
static pg_status read_source(const json &j, const char *path, pg_planet_meta *m, pg_error *err) {
    auto it = j.find("source");
    if (it == j.end()) return PG_OK;
    double e;
    if (!it->is_object() || !get_str(*it, "file", m->source_file, sizeof m->source_file) ||
        !m->source_file[0] || std::strchr(m->source_file, '/') ||
        !std::strcmp(m->source_file, "..") || !std::strcmp(m->source_file, "."))
        return pg_error_set(err, PG_ERR_BADINPUT,
                            "%s: source.file missing or not a file name in the planet directory",
                            path);
    if (!get_num(*it, "exemplar_face_size", 1, 8192, &e) || e != std::floor(e))
        return pg_error_set(err, PG_ERR_BADINPUT,
                            "%s: source.exemplar_face_size missing or not in 1..8192", path);
    if (!get_str(*it, "exemplar_projection", m->source_projection, sizeof m->source_projection))
        return pg_error_set(err, PG_ERR_BADINPUT, "%s: source.exemplar_projection missing", path);
    m->source_face_size = (int)e;
    m->has_source = true;
    return PG_OK;
}

// Optional; when present, a share in [0, 1].
static pg_status read_closed_share(const json &j, const char *path, pg_planet_meta *m,
                                   pg_error *err) {
    const char *key = "closed_land_share_before_final";
    m->closed_land_share_before_final = NAN;
    if (j.find(key) == j.end()) return PG_OK;
    if (!get_num(j, key, 0, 1, &m->closed_land_share_before_final))
        return pg_error_set(err, PG_ERR_BADINPUT, "%s: %s not a number in [0, 1]", path, key);
    return PG_OK;
}

extern "C" pg_status pg_planet_meta_read(const char *path, pg_planet_meta *m, pg_error *err) {
    std::memset(m, 0, sizeof *m);
    std::ifstream in(path);
    if (!in) return pg_error_set(err, PG_ERR_BADINPUT, "%s: cannot open", path);
    json j = json::parse(in, nullptr, false);
    if (j.is_discarded() || !j.is_object())
        return pg_error_set(err, PG_ERR_BADINPUT, "%s: not valid JSON", path);
    double v[6];
    char seed[32];
    if (!get_num(j, "format_version", 1, 1, &v[0]))
        return pg_error_set(err, PG_ERR_BADINPUT, "%s: format_version missing or unsupported",
                            path);
    if (!get_num(j, "radius_m", 1, 1e12, &v[1]))
        return pg_error_set(err, PG_ERR_BADINPUT, "%s: radius_m missing or not > 0", path);
    if (!get_num(j, "flattening", 0, 0.999999, &v[2]))
        return pg_error_set(err, PG_ERR_BADINPUT, "%s: flattening missing or outside [0, 1)", path);
    if (!get_num(j, "tiles", 1, 4096, &v[3]) || v[3] != std::floor(v[3]))
        return pg_error_set(err, PG_ERR_BADINPUT, "%s: tiles missing or not in 1..4096", path);
    if (!get_num(j, "tile_size", 1, 8192, &v[4]) || v[4] != std::floor(v[4]) ||
        ((int)v[4] & ((int)v[4] - 1)) != 0)
        return pg_error_set(err, PG_ERR_BADINPUT,
                            "%s: tile_size missing or not a power of two <= 8192", path);
    if ((double)v[3] * v[4] > 65536)
        return pg_error_set(err, PG_ERR_BADINPUT, "%s: tiles x tile_size above 65536", path);
    if (!get_num(j, "sea_level_m", -1e5, 1e5, &v[5]))
        return pg_error_set(err, PG_ERR_BADINPUT, "%s: sea_level_m missing or absurd", path);
    if (!get_str(j, "projection", m->projection, sizeof m->projection))
        return pg_error_set(err, PG_ERR_BADINPUT, "%s: projection missing", path);
    if (!get_str(j, "seed", seed, sizeof seed))
        return pg_error_set(err, PG_ERR_BADINPUT, "%s: seed missing", path);
    char *end = nullptr;
    m->seed = std::strtoull(seed, &end, 10);
    if (!*seed || *end) return pg_error_set(err, PG_ERR_BADINPUT, "%s: seed not a number", path);
    get_str(j, "exemplar", m->exemplar, sizeof m->exemplar);
    pg_status st = read_source(j, path, m, err);
    if (st == PG_OK) st = read_closed_share(j, path, m, err);
    if (st != PG_OK) return st;
    m->format_version = (int)v[0];
    m->ellipsoid.a = v[1];
    m->ellipsoid.f = v[2];
    m->tiles = (int)v[3];
    m->tile_size = (int)v[4];
    m->sea_level = v[5];
    return PG_OK;
}
