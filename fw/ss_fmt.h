/* Decimal text without printf, for the fixed-point images: newlib's printf family links its double
 * formatter (__aeabi_d*), which the q images must not (cmake/check_no_float.cmake). */
#ifndef SS_FMT_H
#define SS_FMT_H

#include <stddef.h>
#include <stdint.h>

/* Longest text ss_fmt_i64 writes: "-9223372036854775808" */
#define SS_FMT_I64_MAX 20u

/* Write v in decimal at out (no terminator; out holds SS_FMT_I64_MAX chars); returns the count. */
size_t ss_fmt_i64(char *out, int64_t v);

/* Append s, then v in decimal, to line at *len (the caller sized line for it). */
void ss_fmt_put_str(char *line, size_t *len, const char *s);
void ss_fmt_put_i64(char *line, size_t *len, int64_t v);

#endif /* SS_FMT_H */
