/*
 * source.c — where the parser's tokens come from: the scene file, the files
 * it #includes, the lexer of the file being read with its one token of
 * lookahead (p->tok), and the messages about that token ("... expected,
 * got ...") and about nesting.
 *
 * Algorithm: a file is read whole, copied into the scene's arena (tokens,
 * names and locations point into it until the scene is freed) and lexed
 * token by token.  #include resolves its name relative to the directory of
 * the including file (an absolute name as it is), pushes a new lexer — the
 * old one is saved on the C stack — and reads the included file's
 * statements in place; at its end the old lexer resumes.  `#include
 * "colors.inc"` reads no file: it declares the built-in colours (colors.c).
 *
 * Invariants and limits: include_stack[0..include_depth] holds the
 * canonical (real) paths of the files open, the current one last;
 * include_depth <= CSG_PARSE_MAX_INCLUDE, so the recursion through
 * #include is bounded; a file already on the stack is a cycle, reported at
 * the #include.  p->nesting counts the objects, parentheses and vector
 * literals open around the current token (lang_enter / lang_leave) and
 * never exceeds CSG_PARSE_MAX_NESTING, which bounds the grammar's recursion.
 */
#include <errno.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "parse_internal.h"

/* ---- messages about the current token --------------------------------------- */

static bool is_unsupported(const csg_token *t)
{
    return (t->kind == CSG_TOK_WORD || t->kind == CSG_TOK_DIRECTIVE) && t->kw == CSG_KW_UNSUPPORTED;
}

static bool unsupported(parser *p)
{
    char what[64];
    csg_token_describe(&p->tok, what, sizeof what);
    csg_error(p->d, p->tok.loc,
              "unsupported: %s is not in csgtrace's language (see scenes/LANGUAGE.md)", what);
    return false;
}

/* "<what expected ...>, got <token>" — or the unsupported-word message. */
bool lang_expected(parser *p, const char *what)
{
    if (is_unsupported(&p->tok))
        return unsupported(p);
    char got[64];
    csg_token_describe(&p->tok, got, sizeof got);
    csg_error(p->d, p->tok.loc, "%s, got %s", what, got);
    return false;
}

/* "'}' expected (to close 'union' at 12:3), got 'sphere'" */
bool lang_expected_close(parser *p, char closer, const char *opener, csg_loc at)
{
    char what[128];
    snprintf(what, sizeof what, "'%c' expected (to close '%s' at %d:%d)", closer, opener,
             at.line, at.col);
    return lang_expected(p, what);
}

/* Consumes "{" after the keyword `name`. */
bool lang_expect_open(parser *p, const char *name)
{
    if (!lang_is_punct(p, '{')) {
        char what[64];
        snprintf(what, sizeof what, "'{' expected after '%s'", name);
        return lang_expected(p, what);
    }
    return lang_next(p);
}

/* "';' expected (to end '#declare' at 3:1), got 'sphere'" */
bool lang_expect_semicolon(parser *p, const char *directive, csg_loc at)
{
    if (!lang_is_punct(p, ';')) {
        char what[128];
        snprintf(what, sizeof what, "';' expected (to end '#%s' at %d:%d)", directive, at.line,
                 at.col);
        return lang_expected(p, what);
    }
    return lang_next(p);
}

bool lang_enter(parser *p, csg_loc loc)
{
    if (++p->nesting > CSG_PARSE_MAX_NESTING) {
        csg_error(p->d, loc, "nesting deeper than %d levels", CSG_PARSE_MAX_NESTING);
        return false;
    }
    return true;
}

void lang_leave(parser *p)
{
    p->nesting--;
}

/* ---- files -------------------------------------------------------------------- */

/* Reads a whole file into malloc'd memory. */
char *lang_read_file(const char *path, size_t *len, int *err)
{
    FILE *f = fopen(path, "rb");
    if (!f) {
        *err = errno;
        return NULL;
    }
    size_t cap = 4096, n = 0;
    char *buf = malloc(cap);
    while (buf) {
        if (n == cap) {
            char *more = cap > SIZE_MAX / 2 ? NULL : realloc(buf, cap * 2);
            if (!more) {
                free(buf);
                buf = NULL;
                *err = ENOMEM;
                break;
            }
            buf = more;
            cap *= 2;
        }
        size_t got = fread(buf + n, 1, cap - n, f);
        n += got;
        if (got == 0) {
            if (ferror(f)) {
                *err = errno ? errno : EIO;
                free(buf);
                buf = NULL;
            }
            break;
        }
    }
    if (!buf && *err == 0)
        *err = ENOMEM;
    fclose(f);
    *len = n;
    return buf;
}

/* The canonical name of a file for cycle detection: its real path when it
 * exists, the path itself otherwise (a csg_parse_string name). */
static const char *canonical(parser *p, const char *path)
{
    char *real = realpath(path, NULL);
    const char *r = lang_strndup(p, real ? real : path, strlen(real ? real : path));
    free(real);
    return r;
}

/* Reads `text` as the statements of file `path` (already in the arena). */
static bool parse_source(parser *p, const char *path, const char *text, size_t len)
{
    csg_lexer_init(&p->lx, path, text, len);
    return lang_next(p) && lang_parse_statements(p);
}

bool lang_parse_main(parser *p, const char *path, const char *text, size_t len)
{
    p->include_stack[0] = canonical(p, path);
    if (!p->include_stack[0])
        return false;
    return parse_source(p, path, text, len);
}

/* ---- #include ----------------------------------------------------------------- */

/* The path of the included file `name` (a string token): relative to the
 * including file's directory unless it is absolute; in the arena. */
static char *include_path(parser *p, const csg_token *name)
{
    const char *cur = p->lx.file;
    const char *slash = strrchr(cur, '/');
    size_t dirlen = (name->text[0] != '/' && slash) ? (size_t)(slash - cur + 1) : 0;
    char *path = lang_alloc(p, dirlen + name->len + 1);
    if (!path)
        return NULL;
    memcpy(path, cur, dirlen);
    memcpy(path + dirlen, name->text, name->len);
    return path;
}

/* Whether `path` may be opened by the #include at `at`: not too deep, not
 * a file being read already; *canon its canonical name. */
static bool may_include(parser *p, csg_loc at, const char *path, const char **canon)
{
    if (p->include_depth >= CSG_PARSE_MAX_INCLUDE) {
        csg_error(p->d, at, "#include nested deeper than %d files", CSG_PARSE_MAX_INCLUDE);
        return false;
    }
    *canon = canonical(p, path);
    if (!*canon)
        return false;
    for (int i = 0; i <= p->include_depth; i++) {
        if (strcmp(p->include_stack[i], *canon) == 0) {
            csg_error(p->d, at, "#include cycle: '%s' is already being read", path);
            return false;
        }
    }
    return true;
}

/* The text of the included file, copied into the arena. */
static char *read_include(parser *p, csg_loc at, const char *path, size_t *len)
{
    int err = 0;
    char *text = lang_read_file(path, len, &err);
    if (!text) {
        csg_error(p->d, at, "cannot read include file '%s': %s", path, strerror(err));
        return NULL;
    }
    char *copy = lang_strndup(p, text, *len);
    free(text);
    return copy;
}

/* Reads the statements of the included file, then resumes the including
 * one after the #include. */
static bool parse_nested(parser *p, const char *canon, const char *path, const char *text,
                         size_t len)
{
    csg_lexer saved = p->lx;
    p->include_stack[++p->include_depth] = canon;
    if (!parse_source(p, path, text, len))
        return false;
    p->include_depth--;
    p->lx = saved;
    return lang_next(p);
}

bool lang_parse_include(parser *p)
{
    csg_loc at = p->tok.loc;
    if (!lang_next(p))
        return false;
    if (p->tok.kind != CSG_TOK_STRING)
        return lang_expected(p, "a file name in quotes expected after '#include'");
    csg_token name = p->tok;
    if (name.len == strlen("colors.inc") && memcmp(name.text, "colors.inc", name.len) == 0)
        return lang_declare_builtin_colors(p) && lang_next(p);
    if (memchr(name.text, '\0', name.len) || name.len == 0) {
        csg_error(p->d, at, "#include: invalid file name");
        return false;
    }
    const char *path = include_path(p, &name);
    const char *canon;
    if (!path || !may_include(p, at, path, &canon))
        return false;
    size_t len = 0;
    const char *text = read_include(p, at, path, &len);
    return text && parse_nested(p, canon, path, text, len);
}
