/** @file vi_scene_edit.h
 * Command-line overrides of scene keys (`--set KEY=VALUE`): part of the
 * companion library vibroimpact_scene.
 *
 * KEY is a dotted path into the YAML document, with 1-based list indices in
 * brackets: `forcing.omega`, `stop.xs`, `forcing.a[1]`, `model.chain.c`.
 * The document is loaded with libyaml to find the node; its text span is
 * then replaced in the scene text itself, so comments, layout and every line
 * number stay as the user wrote them and a bad value is still reported at
 * file:line:column of the key it overrides.  A key the scene lacks is added
 * to the innermost mapping that exists (flow mappings on the same line;
 * block mappings on a new line after their last entry, so lines below it
 * move down by one); list elements are never added.  VALUE must be one
 * YAML node on one line (a number, a word, or a flow list such as [0.5, 0]).
 *
 * Life cycle: vi_scene_edit_create -> vi_scene_edit_set (any number) ->
 * vi_scene_edit_parse (a validated vi_scene of the edited text) ->
 * vi_scene_edit_destroy.  One edit per thread.
 */
#ifndef VI_SCENE_EDIT_H
#define VI_SCENE_EDIT_H

#include <stdint.h>

#include "vibroimpact/vi_export.h"
#include "vibroimpact/vi_scene.h"

#ifdef __cplusplus
extern "C" {
#endif

/** Opaque scene text under edit. */
typedef struct vi_scene_edit vi_scene_edit;

/** Start editing a copy of the YAML `text` (len < 0: NUL-terminated);
 *  `name` is the file name used in messages.  The text must be valid YAML
 *  (not necessarily a valid scene).  @return VI_OK, VI_ERR_ARG, VI_ERR_PARSE
 *  (YAML syntax, at its line in diag), VI_ERR_LIMIT (nested deeper than
 *  the scene reader's VI_SCENE_MAX_DEPTH, with its message), VI_ERR_NOMEM. */
VI_API int vi_scene_edit_create(const char *text, int64_t len, const char *name,
                                vi_scene_edit **out, vi_diag *diag);
/** vi_scene_edit_create with a nesting limit, as vi_scene_parse_limited:
 *  at most max_depth levels of YAML nesting (<= 0: VI_SCENE_MAX_DEPTH), in
 *  the text, in every value set, and in vi_scene_edit_parse.  The limit
 *  is checked by a scan that stops at the first level too deep, before
 *  the document is loaded.  @return as vi_scene_edit_create (VI_ERR_LIMIT
 *  naming max_depth). */
VI_API int vi_scene_edit_create_limited(const char *text, int64_t len,
                                        const char *name, int max_depth,
                                        vi_scene_edit **out, vi_diag *diag);
/** Destroy and set *e to NULL; NULL-safe. */
VI_API void vi_scene_edit_destroy(vi_scene_edit **e);

/** Set the node at `key` to `value`.  @return VI_OK, VI_ERR_ARG (NULL
 *  arguments), VI_ERR_PARSE (malformed key; a path through a scalar; a list
 *  index out of range; a value that is not one YAML node on one line),
 *  VI_ERR_NOMEM; diag names the key and, where one exists, its line. */
VI_API int vi_scene_edit_set(vi_scene_edit *e, const char *key,
                             const char *value, vi_diag *diag);
/** Apply "KEY=VALUE" (split at the first '=').  Returns as vi_scene_edit_set. */
VI_API int vi_scene_edit_assign(vi_scene_edit *e, const char *assignment,
                                vi_diag *diag);
/** Set `key` to a number (written with 17 significant digits). */
VI_API int vi_scene_edit_set_number(vi_scene_edit *e, const char *key,
                                    double value, vi_diag *diag);
/** The scalar at `key` as written in the text, into buf [len]; VI_ERR_PARSE
 *  if the key is missing or not a scalar, VI_ERR_LIMIT if the value does
 *  not fit in buf (nothing is returned truncated). */
VI_API int vi_scene_edit_get(const vi_scene_edit *e, const char *key,
                             char *buf, int len, vi_diag *diag);
/** The current text (owned by the edit, valid until its next change). */
VI_API const char *vi_scene_edit_text(const vi_scene_edit *e);
/** Parse and validate the current text (vi_scene_parse under the original
 *  name).  An error on a line the edits changed says so in its message.
 *  @return as vi_scene_parse. */
VI_API int vi_scene_edit_parse(const vi_scene_edit *e, vi_scene **out,
                               vi_diag *diag);
/** vi_scene_edit_parse within a memory budget, as vi_scene_load_within.
 *  @return as vi_scene_edit_parse, VI_ERR_LIMIT, VI_ERR_ARG (NaN). */
VI_API int vi_scene_edit_parse_within(const vi_scene_edit *e,
                                      double max_memory, vi_scene **out,
                                      vi_diag *diag);

#ifdef __cplusplus
}
#endif
#endif
