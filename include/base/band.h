/* band.h: LU factorisation with partial pivoting of a square banded matrix
 * (half bandwidths kl = ku) and its solves, in LAPACK's band storage: the
 * arithmetic of dgbtf2 and dgbtrs, written out, because the library's
 * per-column BLAS calls cost more than their arithmetic at the sizes of a
 * rod's step (docs/decisions/0022-band-lu-profile.md). The same
 * numbers bit for bit whatever the path (rows or columns, any kl). */
#ifndef RODSIM_BASE_BAND_H
#define RODSIM_BASE_BAND_H

typedef struct band_lu {
    int n;            /* unknowns */
    int kl;           /* half bandwidth in use (kl = ku), at most the one created with */
    int ldab;         /* rows of storage: 3 kl + 1 of the kl created with (2 kl + ku + 1:
                         U gains kl diagonals by pivoting) */
    double *ab;       /* (ldab x n) column-major: A(i, j) at ab[2 kl + i - j + j ldab]
                         before band_factor, its L and U after */
    int *pivot;       /* (n) row interchanges, 1-based (LAPACK's ipiv) */
    double *inv_diag; /* (n) 1 / U_jj: the back substitution multiplies instead of dividing
                         (a division's latency sits on its serial critical path) */
    int *lower;       /* (n) the length of column j's loops over L below the diagonal: its
                         trailing zeros trimmed, then padded with them to 8 where that is
                         shorter than the band */
    int *upper;       /* (n) the first row of U's column j that is not zero */
    double *rows;     /* band_solve_rows' scratch (32-byte aligned), NULL when not made */
} band_lu;

/* Allocates the storage of an n x n matrix of half bandwidth kl (ab zeroed),
 * with band_solve_rows' scratch when `rows` is set. Returns 0, or -1 when
 * out of memory (then band_lu_destroy frees what was made). */
int band_lu_create(band_lu *lu, int n, int kl, int rows);
void band_lu_destroy(band_lu *lu);

/* LU of ab in place with partial pivoting, its columns before `from`
 * factored already (from > 0: the columns from `from` on hold the matrix,
 * and the steps before whose interchanges and updates reach them are applied
 * again, so the factors are those of a factorisation from 0, bit for bit).
 * Returns LAPACK's info: 0, or the first zero pivot's column + 1. */
int band_factor(band_lu *lu, int from);

/* Solves A x = b in place with the factors, one right-hand side. */
void band_solve(const band_lu *lu, double *b);

/* The same for `count` right-hand sides (column-major, n apart) whose rows
 * above `first` are 0: by rows (band_solve_rows) when the scratch was made
 * and count > 1, else one column at a time. */
void band_solve_many(const band_lu *lu, double *b, int count, int first);

/* band_solve_many by rows: up to 4 LANES right-hand sides side by side,
 * each step of the substitutions one vector operation for LANES of them.
 * Needs the rows scratch (band_lu_create's `rows`). */
void band_solve_rows(const band_lu *lu, double *b, int count, int first);

/* band_solve_rows for count right-hand sides given by their entries:
 * column c is 0 but for value[k] added at row[k], in order, for k =
 * start[c] .. start[c + 1] - 1, none above row `first`. The solutions go
 * into b (column-major, n apart; nothing in it is read): the numbers
 * band_solve_rows gives for those columns written out, without writing
 * them out. Needs the rows scratch. */
void band_solve_entries(const band_lu *lu, double *b, int count, int first, const int *start,
                        const int *row, const double *value);

#endif
