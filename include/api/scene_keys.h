/* scene_keys.h: the one table of every key a scene may hold, with unit,
 * default, accepted values and meaning. The strict check of a scene
 * (ini_check_keys, before any value is read) and `rodsim help scene` /
 * `rodsim help beam` (the README's scene reference) both use these tables;
 * tests/cli/test_scene_keys.c holds the readers to them: every key a reader
 * asks for is in its table, every table key is read, and every default
 * written here is the value the reader uses when the key is absent.
 *
 * Decision: the tables live in the api layer because a rod scene mixes
 * sections owned by two layers (sim reads [rod] .. [physics], render reads
 * [render]); the api, the lowest layer that composes them, knows both, and
 * the cli and the library (rodsim.h) read scenes through it. */
#ifndef RODSIM_SCENE_KEYS_H
#define RODSIM_SCENE_KEYS_H

#include <stdio.h>

#include "base/ini.h"

/* `rodsim run` scenes: [rod] [solver] [tip] [loads] [ends] [physics] [render]. */
extern const ini_key scene_keys_rod[];
/* `rodsim fem` scenes: [material] [geometry] [support]... [load]... [plot]. */
extern const ini_key scene_keys_beam[];

/* Prints the reference of a table as Markdown: a short paragraph on the
 * syntax, then one table row per key (key as --set writes it, unit, default,
 * accepted, meaning). */
void scene_keys_print_markdown(FILE *f, const ini_key *table);

#endif
