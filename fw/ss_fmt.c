#include "ss_fmt.h"

size_t ss_fmt_i64(char *out, int64_t v)
{
    /* the magnitude as unsigned: -INT64_MIN does not fit int64 */
    uint64_t m = (v < 0) ? (uint64_t)0 - (uint64_t)v : (uint64_t)v;
    char rev[SS_FMT_I64_MAX];
    size_t n = 0;
    do {
        rev[n++] = (char)('0' + (int)(m % 10u));
        m /= 10u;
    } while (m != 0u);
    size_t k = 0;
    if (v < 0) {
        out[k++] = '-';
    }
    while (n > 0u) {
        out[k++] = rev[--n];
    }
    return k;
}

void ss_fmt_put_str(char *line, size_t *len, const char *s)
{
    while (*s != '\0') {
        line[(*len)++] = *s++;
    }
}

void ss_fmt_put_i64(char *line, size_t *len, int64_t v)
{
    *len += ss_fmt_i64(line + *len, v);
}
