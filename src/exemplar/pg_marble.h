/* pg_marble.h - where Debian's marble-qt-data keeps the default exemplar (data/README.md):
 * NASA Blue Marble and Marble's tiled global relief. Library-internal: a program picks
 * them through pg_exemplar_opts' NULL paths (pg_exemplar.h). */
#ifndef PG_MARBLE_H
#define PG_MARBLE_H

#ifdef __cplusplus
extern "C" {
#endif

#define PG_MARBLE_DIR "/usr/share/marble/data/maps/earth"
#define PG_MARBLE_ALBEDO PG_MARBLE_DIR "/bluemarble/bluemarble.jpg"
#define PG_MARBLE_RELIEF_DIR PG_MARBLE_DIR "/srtm/3"
#define PG_MARBLE_RELIEF_ROWS 8
#define PG_MARBLE_RELIEF_COLS 16

#ifdef __cplusplus
}
#endif

#endif
