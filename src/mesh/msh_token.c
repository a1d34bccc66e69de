/* msh_token.c - the gmsh reader's token layer (see msh_impl.h): integers, sizes,
 * reals and words, read as text (strtol/strtod, whitespace-separated) or as raw
 * binary fields (format 4.1 binary: ints 4 bytes, sizes 8, doubles 8, in this
 * machine's byte order, checked by the caller). Every count read is checked
 * against the bytes that remain, so a corrupted count can never make the reader
 * allocate or loop beyond the file. */
#include "msh_impl.h"
#include <errno.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static long LineOf(const Parser *p, size_t pos)
{
  long line = 1;
  for (size_t i = 0; i < pos && i < p->len; i++)
    if (p->buf[i] == '\n') line++;
  return line;
}

int MshKeepError(char *err, size_t len, int *failed, const char *where, const char *fmt, va_list ap)
{
  char what[1024];
  if (*failed) return 1;
  vsnprintf(what, sizeof(what), fmt, ap);
  snprintf(err, len, "%s: %s", where, what);
  *failed = 1;
  return 1;
}

int MshFail(Parser *p, const char *fmt, ...)
{
  char    where[4200];
  va_list ap;
  if (p->failed) return 1;
  if (p->binary) snprintf(where, sizeof(where), "mesh file '%s' (binary), byte %zu%s%s", p->path, p->pos, p->section ? " in " : "", p->section ? p->section : "");
  else snprintf(where, sizeof(where), "mesh file '%s', line %ld%s%s", p->path, LineOf(p, p->pos), p->section ? " in " : "", p->section ? p->section : "");
  va_start(ap, fmt);
  MshKeepError(p->err, p->errlen, &p->failed, where, fmt, ap);
  va_end(ap);
  return 1;
}

static int IsSpace(char c)
{
  return c == ' ' || c == '\t' || c == '\r' || c == '\n';
}

void MshSkipSpace(Parser *p)
{
  while (p->pos < p->len && IsSpace(p->buf[p->pos])) p->pos++;
}

size_t MshRemaining(const Parser *p)
{
  return p->len - p->pos;
}

int MshReadLong(Parser *p, long *v)
{
  char *end;
  MshSkipSpace(p);
  if (p->pos >= p->len) return MshFail(p, "unexpected end of file (expected an integer)");
  errno = 0;
  *v    = strtol(p->buf + p->pos, &end, 10);
  if (end == p->buf + p->pos || errno) return MshFail(p, "expected an integer");
  if (end < p->buf + p->len && !IsSpace(*end)) return MshFail(p, "expected an integer");
  p->pos = (size_t)(end - p->buf);
  return 0;
}

/* binary: n raw bytes in the file's (= this machine's, checked) byte order */
static int ReadRaw(Parser *p, void *v, size_t n, const char *what)
{
  if (MshRemaining(p) < n) return MshFail(p, "unexpected end of file (expected %s)", what);
  memcpy(v, p->buf + p->pos, n);
  p->pos += n;
  return 0;
}

int MshReadInt(Parser *p, long *v)
{
  int i = 0;
  if (!p->binary) return MshReadLong(p, v);
  if (ReadRaw(p, &i, sizeof(i), "an integer")) return 1;
  *v = i;
  return 0;
}

int MshReadSize(Parser *p, long *v)
{
  unsigned long long u = 0;
  if (!p->binary) return MshReadLong(p, v);
  if (ReadRaw(p, &u, sizeof(u), "a size")) return 1;
  if (u > (unsigned long long)1 << 62) return MshFail(p, "size %llu is not plausible (corrupted file?)", u);
  *v = (long)u;
  return 0;
}

/* a node or element tag: a size field that must be positive (a negative tag
 * written in binary arrives as a huge unsigned value: shown signed) */
int MshReadTag(Parser *p, long *v, const char *what)
{
  if (p->binary) {
    long long s = 0;
    if (ReadRaw(p, &s, sizeof(s), "a tag")) return 1;
    if (s <= 0 || s > (long long)1 << 62) return MshFail(p, "%s tag %lld is not positive", what, s);
    *v = (long)s;
    return 0;
  }
  if (MshReadLong(p, v)) return 1;
  if (*v <= 0) return MshFail(p, "%s tag %ld is not positive", what, *v);
  return 0;
}

int MshBinaryStart(Parser *p)
{
  if (!p->binary) return 0;
  if (p->pos < p->len && p->buf[p->pos] == '\r') p->pos++;
  if (p->pos >= p->len || p->buf[p->pos] != '\n') return MshFail(p, "expected a line break before the binary data");
  p->pos++;
  return 0;
}

int MshReadDouble(Parser *p, double *v)
{
  char *end;
  if (p->binary) {
    if (ReadRaw(p, v, sizeof(*v), "a real number")) return 1;
    if (!(*v == *v) || *v > 1e300 || *v < -1e300) return MshFail(p, "coordinate is not a finite number");
    return 0;
  }
  MshSkipSpace(p);
  if (p->pos >= p->len) return MshFail(p, "unexpected end of file (expected a number)");
  errno = 0;
  *v    = strtod(p->buf + p->pos, &end);
  if (end == p->buf + p->pos || errno) return MshFail(p, "expected a real number");
  if (end < p->buf + p->len && !IsSpace(*end)) return MshFail(p, "expected a real number");
  if (!(*v == *v) || *v > 1e300 || *v < -1e300) return MshFail(p, "coordinate is not a finite number");
  p->pos = (size_t)(end - p->buf);
  return 0;
}

/* a count that the rest of the file could possibly hold (each item >= bytes_per_item bytes) */
int MshReadCount(Parser *p, long *v, long bytes_per_item, const char *what)
{
  if (MshReadSize(p, v)) return 1;
  if (*v < 0) return MshFail(p, "negative %s", what);
  if ((size_t)*v > MshRemaining(p) / (size_t)bytes_per_item + 1) return MshFail(p, "%s %ld is larger than the rest of the file can hold (truncated or corrupted file?)", what, *v);
  return 0;
}

int MshReadWord(Parser *p, char *w, size_t n)
{
  size_t k = 0;
  MshSkipSpace(p);
  if (p->pos >= p->len) return MshFail(p, "unexpected end of file");
  while (p->pos < p->len && !IsSpace(p->buf[p->pos])) {
    if (k + 1 < n) w[k++] = p->buf[p->pos];
    p->pos++;
  }
  w[k] = 0;
  return 0;
}

int MshExpect(Parser *p, const char *word)
{
  char w[64];
  if (MshReadWord(p, w, sizeof(w))) return 1;
  if (strcmp(w, word)) return MshFail(p, "expected '%s', found '%.40s' (truncated or corrupted file?)", word, w);
  return 0;
}
