/* suggest.c: see suggest.h. */
#include "base/suggest.h"

#include <string.h>

int suggest_distance(const char *a, const char *b)
{
    /* optimal string alignment: Levenshtein plus swaps of neighbours */
    enum { MAX = 64 };
    int n = (int)strlen(a), m = (int)strlen(b);
    if (n >= MAX) n = MAX - 1;
    if (m >= MAX) m = MAX - 1;
    static const int cap = 255;
    int d[MAX][MAX];
    for (int i = 0; i <= n; i++) d[i][0] = i;
    for (int j = 0; j <= m; j++) d[0][j] = j;
    for (int i = 1; i <= n; i++) {
        for (int j = 1; j <= m; j++) {
            int cost = a[i - 1] == b[j - 1] ? 0 : 1;
            int best = d[i - 1][j] + 1;
            if (d[i][j - 1] + 1 < best) best = d[i][j - 1] + 1;
            if (d[i - 1][j - 1] + cost < best) best = d[i - 1][j - 1] + cost;
            if (i > 1 && j > 1 && a[i - 1] == b[j - 2] && a[i - 2] == b[j - 1] &&
                d[i - 2][j - 2] + 1 < best)
                best = d[i - 2][j - 2] + 1;
            d[i][j] = best;
        }
    }
    return d[n][m] < cap ? d[n][m] : cap;
}

int suggest_near(const char *word, const char *name, int *distance)
{
    int n = (int)strlen(word);
    int limit = n <= 4 ? 1 : n <= 8 ? 2 : 3;
    int d = suggest_distance(word, name);
    if (n >= 3 && strncmp(word, name, (size_t)n) == 0) d = d < limit ? d : limit;
    *distance = d;
    return d <= limit && d < n;
}

const char *suggest_nearest(const char *word, const char *const *names)
{
    const char *best = NULL;
    int best_d = 256;
    for (int i = 0; names[i]; i++) {
        int d;
        if (strcmp(word, names[i]) == 0) return NULL;
        if (suggest_near(word, names[i], &d) && d < best_d) {
            best = names[i];
            best_d = d;
        }
    }
    return best;
}
