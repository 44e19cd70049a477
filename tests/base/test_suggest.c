/* test_suggest.c: the edit distance against hand-counted edits, and the
 * nearest name offered for a typo ("rnu" -> run, "implict" -> implicit). */
#include "base/suggest.h"
#include "test.h"

static void distance_is(const char *a, const char *b, int expected, const char *why)
{
    int d = suggest_distance(a, b);
    check(d == expected, "distance(%s, %s) = %d, expected %d (%s)", a, b, d, expected, why);
}

static void nearest_is(const char *word, const char *const *names, const char *expected)
{
    const char *near = suggest_nearest(word, names);
    int ok = expected ? near && strcmp(near, expected) == 0 : near == NULL;
    check(ok, "nearest to '%s': %s, expected %s", word, near ? near : "(none)",
          expected ? expected : "(none)");
}

int main(void)
{
    distance_is("implict", "implicit", 1, "one insertion");
    distance_is("lenght", "length", 1, "one swap of neighbours");
    distance_is("kitten", "sitting", 3, "two substitutions, one insertion");
    distance_is("", "abc", 3, "three insertions");
    distance_is("same", "same", 0, "equal words");
    distance_is("rnu", "run", 1, "one swap");

    static const char *const commands[] = {"run", "fem", "live", "render", "sweep",
                                           "stability", "figure", "validate", "version", NULL};
    nearest_is("rnu", commands, "run");
    nearest_is("swep", commands, "sweep");
    nearest_is("valdiate", commands, "validate");
    nearest_is("run", commands, NULL);       /* accepted as it is: nothing to suggest */
    nearest_is("xyzzy", commands, NULL);     /* too far from every name */
    nearest_is("stab", commands, "stability"); /* the start of a name */
    static const char *const schemes[] = {"thesis", "implicit", "static", NULL};
    nearest_is("implict", schemes, "implicit");
    nearest_is("statc", schemes, "static");
    nearest_is("tesis", schemes, "thesis");
    nearest_is("euler", schemes, NULL);
    static const char *const ends[] = {"clamped", "pinned", "free", NULL};
    nearest_is("clampd", ends, "clamped");
    nearest_is("fre", ends, "free");
    return test_finish();
}
