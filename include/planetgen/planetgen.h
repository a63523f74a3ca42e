/* planetgen.h - the whole public API of libplanetgen in one include:
 *
 *     #include <planetgen/planetgen.h>
 *     cc prog.c $(pkg-config --cflags --libs planetgen)
 *
 * planetgen generates whole planets by example: an exemplar (a global albedo and
 * height map, pg_exemplar.h) is prepared into a synthesis pyramid (pg_synth.h) and
 * synthesized onto a cube sphere (pg_cube.h) tile by tile (pg_planet_synth.h); pits
 * are removed (pg_pits.h), the planet is saved, exported (pg_export.h) and inspected
 * (pg_inspect.h, pg_realism.h). examples/generate_small.c is a complete program.
 *
 * The rules below hold for every function of every header included here; the headers
 * state only the exceptions.
 *
 * RESULTS AND ERRORS (pg_common.h). Every function that can fail returns a pg_status
 * (PG_OK = 0) and takes a last argument pg_error *err, a caller-owned struct; err may
 * be NULL. On failure the function writes one human-readable line into err->msg that
 * names the file or the option at fault, and the first error recorded wins, so the
 * root cause survives the unwinding of callers. There is no global error state and no
 * errno convention. A function that cannot fail returns its value directly; a few
 * constructors that can only run out of memory return NULL instead (they say so).
 *
 * MEMORY: THE CALLER OWNS IT. The library never keeps a pointer it was given after
 * the call returns, unless a struct says it borrows one (pg_planet_synth_params'
 * guide, types and dist; pg_drainage_terrain's heights): then the caller keeps it
 * alive for as long as that struct is used.
 *   - Context structs (pg_planet, pg_exemplar, pg_image, pg_guide, ...) live where the
 *     caller puts them; a function that fills one allocates its arrays, and the
 *     caller releases them with the matching pg_X_free (pg_planet_alloc /
 *     pg_planet_load / pg_planet_synth_run -> pg_planet_free, pg_exemplar_load ->
 *     pg_exemplar_free, pg_image_read -> pg_image_free, ...). pg_X_free sets the
 *     pointers it freed to NULL and accepts a zero-initialised struct, so start from
 *     `pg_planet p = {0};` and free on every path. A function that fails releases what
 *     it allocated itself.
 *   - A few objects are allocated whole by the library and handed out as a pointer
 *     (pg_synth_exemplar from pg_synth_prepare_exemplar, pg_json, pg_mpi,
 *     pg_inspect_fid_exemplar); only their own pg_X_free / pg_X_finalize releases
 *     them, once.
 *   - Buffers a function returns through a `T **out` argument, or as a plain pointer,
 *     are malloc'd; the caller free()s them (each such function says "caller frees").
 *   - Options structs are filled with their pg_X_opts_default / pg_X_params_default
 *     first, then changed field by field; a new field gets a default there, so code
 *     written that way keeps working.
 *
 * THREADS. No global mutable state: any number of planets can be built, loaded or
 * inspected at once from different threads, as long as no two threads write the same
 * object. The heavy functions parallelise internally with OpenMP
 * (omp_set_num_threads limits them). pg_mpi is the exception: MPI is initialised
 * once per process (pg_mpi.h).
 *
 * DETERMINISM. Randomness comes only from a hash of (seed, level, texel id); the
 * results of synthesis, pit removal and every measure are bit-identical for any thread
 * count, any tile size and any number of MPI ranks.
 *
 * UNITS AND GEOMETRY. Heights are metres, lengths metres unless a name says km, angles
 * degrees at the API (latitudes geodetic on the planet's ellipsoid, pg_ellipsoid.h).
 * Cube-sphere texels are addressed as in pg_cube.h (faces +X -X +Y -Y +Z -Z, global
 * texel id = face * n * n + y * n + x).
 *
 * NAMES: EVERY HEADER IS NAMED AFTER ITS PREFIX. pg_X.h declares only names beginning
 * pg_X (the type pg_X, functions and types pg_X_*, macros PG_X_*); a header pg_X_Y.h
 * holds one part Y of X's API and declares only names beginning pg_X_ (pg_planet_synth.h:
 * the synthesis driver's pg_planet_synth_* and pg_planet_level; pg_inspect_copy.h: copy
 * detection's pg_inspect_copy_*, pg_inspect_coherence_stat). Enumerators carry a short
 * form of their enum's name (PG_ERR_* of pg_status, PG_SAMPLE_* of
 * pg_image_sample_type, PG_TYPE_* of pg_types_id, PG_LAYOUT_* of pg_planet_layout,
 * PG_VIEW_* of the view ids of pg_views.h). pg_common.h holds the shared basics:
 * pg_status, pg_error and pg_version.
 *
 * WHAT IS NOT HERE. Test-only switches and helpers shared between the library's own
 * source files live in the headers of its module folders (src/<module>/) and are not
 * installed; nor is the reader of planet.json (pg_planet_load reads a planet directory).
 *
 * The headers, lowest layer first (each includes what it needs, so any one of them
 * can also be included alone): */
#ifndef PLANETGEN_PLANETGEN_H
#define PLANETGEN_PLANETGEN_H

/* core: results, images, EXR parts, JSON output */
#include "planetgen/pg_common.h"
#include "planetgen/pg_exr.h"
#include "planetgen/pg_image.h"
#include "planetgen/pg_raster.h"
#include "planetgen/pg_json.h"

/* the cube sphere and geodesy */
#include "planetgen/pg_cube.h"
#include "planetgen/pg_ellipsoid.h"
#include "planetgen/pg_geo.h"

/* the macro world: plates and climate */
#include "planetgen/pg_climate.h"
#include "planetgen/pg_plates.h"

/* the exemplar */
#include "planetgen/pg_calibration.h"
#include "planetgen/pg_equirect.h"
#include "planetgen/pg_exemplar.h"
#include "planetgen/pg_relief.h"

/* pit removal and drainage */
#include "planetgen/pg_drainage.h"
#include "planetgen/pg_pits.h"

/* texture synthesis (Lefebvre-Hoppe) and pit removal inside it */
#include "planetgen/pg_pits_gainpit.h"
#include "planetgen/pg_synth.h"

/* the planet: data model, files, synthesis driver and its controls */
#include "planetgen/pg_guide.h"
#include "planetgen/pg_planet.h"
#include "planetgen/pg_planet_synth.h"
#include "planetgen/pg_planet_tiles.h"
#include "planetgen/pg_types.h"

/* export: glTF binary, EXR, previews */
#include "planetgen/pg_export.h"

/* inspection and realism measures */
#include "planetgen/pg_earthlike.h"
#include "planetgen/pg_inspect.h"
#include "planetgen/pg_inspect_copy.h"
#include "planetgen/pg_inspect_distortion.h"
#include "planetgen/pg_lpips.h"
#include "planetgen/pg_realism.h"
#include "planetgen/pg_view.h"
#include "planetgen/pg_views.h"

/* MPI distribution (built without MPI: one process; mpirun with more ranks is refused) */
#include "planetgen/pg_mpi.h"

#endif
