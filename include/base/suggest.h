/* suggest.h: the name someone most likely meant ("did you mean implicit?")
 * when a word they typed (a command, an option, a scene key or value) is not
 * one of those accepted. */
#ifndef RODSIM_SUGGEST_H
#define RODSIM_SUGGEST_H

/* Edit distance between a and b (insertions, deletions, substitutions and
 * swaps of two neighbours each count 1: "implict" -> "implicit" is 1,
 * "lenght" -> "length" is 1), on at most 63 characters of each, capped at 255. */
int suggest_distance(const char *a, const char *b);

/* 1 when `name` is close enough to `word` to suggest: at most 1 edit for a
 * word of up to 4 characters, 2 up to 8, 3 beyond (and fewer edits than the
 * word has characters), or `word` (3 characters or more) starts `name`.
 * *distance: the distance used to rank candidates. */
int suggest_near(const char *word, const char *name, int *distance);

/* The nearest name of the NULL-terminated list that is near enough to
 * `word`, or NULL (none; also when word is one of them). The first of equals wins. */
const char *suggest_nearest(const char *word, const char *const *names);

#endif
