/*
 * source.c — where the parser's tokens come from: the scene file, the files
 * it #includes and the bodies of the macros it calls (the frames), the
 * current token and its lazy reading, and the messages about that token
 * ("... expected, got ...") and about nesting.
 *
 * Frames: p->frames is a stack of lexers, the innermost last.  A file is
 * read whole (a regular file, at most CSG_PARSE_MAX_FILE bytes), copied
 * into the scene's arena (tokens, names and locations point into it until
 * the scene is freed) and lexed token by token.  A macro call pushes a
 * lexer over the macro's body in its file's text, ending at the body's
 * #end.  At the end of a frame the reading goes on in the frame below: the
 * including file, or the caller of the macro.
 *
 * The current token (p->tok) is read lazily: lang_next only marks it
 * consumed; lang_tok reads the next one and runs it when it is a directive
 * or a macro call (directives.c), in a loop, until a token for the grammar
 * comes (parse_internal.h says why).  lang_tok_raw reads without running.
 *
 * #include: the name (a string expression) is looked for relative to the
 * including file's folder, then to the scene file's, then in each library
 * folder (csg_parse_options, $CSGTRACE_LIBRARY_PATH, POV-Ray's include
 * folder); a file the scene wrote (#fopen ... write) comes before them all
 * (fileio.c keeps it in memory).  "colors.inc" found nowhere is built in (colors.c).  A file whose
 * name has no scene extension (.pov .inc .mcr .map) is `hidden`: an error
 * inside it never quotes its content (csg_parse_string rewrites it).
 *
 * Invariants and limits: include_depth <= CSG_PARSE_MAX_INCLUDE and
 * macro_depth <= CSG_PARSE_MAX_MACRO_DEPTH bound the frames; a file already
 * open is a cycle, reported at the #include; p->nesting counts the objects,
 * parentheses, vector literals and running directives around the current
 * token (lang_enter / lang_leave) and never exceeds CSG_PARSE_MAX_NESTING,
 * which bounds the recursion of the grammar and of the directives; p->tokens
 * <= opt.max_tokens bounds the time.
 */
#include <errno.h>
#include <fcntl.h>
#include <limits.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <sys/stat.h>
#include <unistd.h>

#include "parse_internal.h"

/* Every line and column of a file fits csg_loc's ints. */
_Static_assert(CSG_PARSE_MAX_FILE <= INT_MAX, "a file's positions must fit an int");

/* ---- messages about the current token --------------------------------------- */

static bool is_unsupported(const csg_token *t)
{
    return (t->kind == CSG_TOK_WORD || t->kind == CSG_TOK_DIRECTIVE) && t->kw == CSG_KW_UNSUPPORTED;
}

void lang_describe(parser *p, char *buf, size_t size)
{
    csg_token_describe(&p->tok, buf, size);
}

bool lang_unsupported(parser *p, const char *construct, csg_loc at)
{
    if (p->d->failed)
        return false;
    csg_error(p->d, at, "unsupported: %s is not in csgtrace's language (see scenes/LANGUAGE.md)",
              construct);
    p->unsupported = true;
    p->why.construct = lang_strndup(p, construct, strlen(construct));
    p->why.construct_at = at;
    return false;
}

static bool unsupported_token(parser *p)
{
    char what[64];
    lang_describe(p, what, sizeof what);
    return lang_unsupported(p, what, p->tok.loc);
}

/* "<what expected ...>, got <token>" — or the unsupported-word message. */
bool lang_expected(parser *p, const char *what)
{
    /* a raw token (a name being read) is described as it is */
    const csg_token *t = p->tok_ready && p->tok_raw ? &p->tok : lang_tok(p);
    if (p->d->failed)
        return false;
    if (is_unsupported(t))
        return unsupported_token(p);
    char got[64];
    lang_describe(p, got, sizeof got);
    csg_error(p->d, t->loc, "%s, got %s", what, got);
    return false;
}

static void punct_name(int c, char *buf, size_t size)
{
    const char *two = c == CSG_P_LE ? "<=" : c == CSG_P_GE ? ">=" : c == CSG_P_NE ? "!=" : NULL;
    if (two)
        snprintf(buf, size, "%s", two);
    else
        snprintf(buf, size, "%c", (char)c);
}

/* "'}' expected (to close 'union' at 12:3), got 'sphere'" */
bool lang_expected_close(parser *p, int closer, const char *opener, csg_loc at)
{
    char what[160], name[4];
    punct_name(closer, name, sizeof name);
    snprintf(what, sizeof what, "'%s' expected (to close '%s' at %d:%d)", name, opener, at.line,
             at.col);
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

bool lang_expect_punct(parser *p, int c, const char *context)
{
    if (!lang_is_punct(p, c)) {
        char what[160], name[4];
        punct_name(c, name, sizeof name);
        snprintf(what, sizeof what, "'%s' expected %s", name, context);
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

/* ---- frames -------------------------------------------------------------------- */

frame *lang_frame(parser *p)
{
    return (frame *)p->frames.data + p->frames.count - 1;
}

bool lang_raw_token(parser *p, csg_token *t)
{
    frame *f = lang_frame(p);
    if (++p->tokens > p->opt.max_tokens) {
        csg_loc at = {f->lx.file, f->lx.line, f->lx.col};
        csg_error(p->d, at,
                  "more than %ld tokens read: a loop that never ends? (the limit of one parse)",
                  p->opt.max_tokens);
        return false;
    }
    return csg_lexer_next(&f->lx, t, p->d);
}

bool lang_raw_peek_punct(parser *p, int c)
{
    csg_lexer copy = lang_frame(p)->lx;
    csg_token t;
    csg_diag scratch;
    scratch.failed = 0;
    return csg_lexer_next(&copy, &t, &scratch) && t.kind == CSG_TOK_PUNCT && t.punct == c;
}

static bool push_frame(parser *p, const frame *f)
{
    return lang_vec_push(p, &p->frames, sizeof *f, f);
}

bool lang_push_macro_frame(parser *p, const lang_macro *m, csg_loc call)
{
    if (p->macro_depth >= CSG_PARSE_MAX_MACRO_DEPTH) {
        csg_error(p->d, call, "macro calls nested deeper than %d (a recursion that never ends?)",
                  CSG_PARSE_MAX_MACRO_DEPTH);
        return false;
    }
    frame f;
    memset(&f, 0, sizeof f);
    f.kind = FRAME_MACRO;
    f.lx = m->body;
    f.entered_at = call;
    f.macro = m->name;
    f.cond_base = p->conds.count;
    f.scope = p->scopes.count - 1;
    p->macro_depth++;
    return push_frame(p, &f);
}

bool lang_pop_frame(parser *p)
{
    if (!lang_check_frame_end(p))
        return false;
    frame *f = lang_frame(p);
    if (f->kind == FRAME_MACRO)
        p->macro_depth--;
    else
        p->include_depth--;
    lang_scope_pop(p);
    p->frames.count--;
    return true;
}

/* Reads the next raw token into p->tok, leaving the frames that end. */
static bool read_raw_current(parser *p)
{
    for (;;) {
        if (!lang_raw_token(p, &p->tok))
            return false;
        if (p->tok.kind != CSG_TOK_EOF || p->frames.count == 1)
            break;
        if (!lang_pop_frame(p))
            return false;
    }
    if (p->tok.kind == CSG_TOK_EOF && !lang_check_frame_end(p))
        return false;
    p->tok_ready = true;
    p->tok_raw = true;
    return true;
}

static const csg_token *error_token(parser *p)
{
    memset(&p->tok, 0, sizeof p->tok);
    p->tok.kind = CSG_TOK_ERROR;
    p->tok.text = "";
    p->tok_ready = true;
    p->tok_raw = false;
    return &p->tok;
}

/* A word that names a macro: a call. */
static bool is_macro_call(parser *p, const csg_token *t)
{
    if (t->kind != CSG_TOK_WORD || t->kw != CSG_KW_NONE)
        return false;
    symbol *sym = lang_sym_find(p, t->text, t->len);
    return sym && sym->d.kind == SYM_MACRO;
}

/* Runs directives and macro calls until the current token is one for the
 * grammar (see the top comment). */
static bool resolve(parser *p)
{
    for (;;) {
        if (!p->tok_ready && !read_raw_current(p))
            return false;
        if (!p->tok_raw)
            return true;
        csg_token t = p->tok;
        if (t.kind != CSG_TOK_DIRECTIVE && !is_macro_call(p, &t)) {
            p->tok_raw = false;
            return true;
        }
        p->tok_ready = false;
        if (!lang_enter(p, t.loc) || !lang_run_directive(p, &t))
            return false;
        lang_leave(p);
    }
}

const csg_token *lang_tok_read(parser *p)
{
    if (p->d->failed || !resolve(p))
        return error_token(p);
    return &p->tok;
}

const csg_token *lang_tok_raw(parser *p)
{
    if (p->d->failed || (!p->tok_ready && !read_raw_current(p)))
        return error_token(p);
    return &p->tok;
}

bool lang_next(parser *p)
{
    p->tok_ready = false;
    return !p->d->failed;
}

/* Two frames that would read the same in the chain. */
static bool same_entry(const frame *a, const frame *b)
{
    return a->kind == b->kind && a->entered_at.file == b->entered_at.file &&
           a->entered_at.line == b->entered_at.line && a->entered_at.col == b->entered_at.col &&
           (a->kind == FRAME_MACRO ? a->macro == b->macro : a->lx.src == b->lx.src);
}

/* " (in macro 'M' called at f:1:2, in 'x.inc' included at f:3:4)": the
 * open frames, innermost first, a run of equal ones (a recursion) once
 * with its count, at most 8 entries. */
void lang_frame_chain(parser *p, char *buf, size_t size)
{
    size_t n = 0;
    buf[0] = '\0';
    const frame *fr = p->frames.data;
    int shown = 0;
    for (int i = p->frames.count - 1; i >= 1 && n + 1 < size; i--) {
        const frame *f = &fr[i];
        int run = 1;
        while (i - run >= 1 && same_entry(f, &fr[i - run]))
            run++;
        const char *sep = shown ? ", " : " (";
        if (shown == 8) {
            n += (size_t)snprintf(buf + n, size - n, ", ... %d more", i);
            break;
        }
        if (f->kind == FRAME_MACRO)
            n += (size_t)snprintf(buf + n, size - n, "%sin macro '%s' called at %s:%d:%d", sep,
                                  f->macro, f->entered_at.file, f->entered_at.line,
                                  f->entered_at.col);
        else
            n += (size_t)snprintf(buf + n, size - n, "%sin '%s' included at %s:%d:%d", sep,
                                  f->lx.file, f->entered_at.file, f->entered_at.line,
                                  f->entered_at.col);
        if (run > 1 && n + 1 < size)
            n += (size_t)snprintf(buf + n, size - n, " (%d times)", run);
        i -= run - 1;
        shown++;
    }
    if (shown && n + 1 < size)
        snprintf(buf + n, size - n, ")");
}

/* ---- files -------------------------------------------------------------------- */

static const char *file_type(mode_t m)
{
    return S_ISDIR(m) ? "a directory" : S_ISFIFO(m) ? "a FIFO" : S_ISCHR(m) ? "a character device"
         : S_ISBLK(m) ? "a block device" : S_ISSOCK(m) ? "a socket" : "not a plain file";
}

/* Reads fd (a regular file of `size` bytes) into malloc'd memory. */
static char *read_fd(int fd, off_t size, long max, size_t *len, char *why, size_t why_size)
{
    size_t cap = (size_t)size + 1, n = 0;
    char *buf = malloc(cap + 1);
    if (!buf) {
        snprintf(why, why_size, "%s", strerror(ENOMEM));
        return NULL;
    }
    for (;;) {
        ssize_t got = read(fd, buf + n, cap - n);
        if (got < 0 && errno == EINTR)
            continue;
        if (got < 0) {
            snprintf(why, why_size, "%s", strerror(errno));
            free(buf);
            return NULL;
        }
        if (got == 0)
            break;
        n += (size_t)got;
        if (n == cap) { /* it grew while being read */
            snprintf(why, why_size, "larger than %ld bytes", max);
            free(buf);
            return NULL;
        }
    }
    *len = n;
    return buf;
}

char *lang_read_fd(int fd, long max, size_t *len, char *why, size_t why_size)
{
    struct stat st;
    char *text = NULL;
    if (fstat(fd, &st) != 0)
        snprintf(why, why_size, "%s", strerror(errno));
    else if (!S_ISREG(st.st_mode))
        snprintf(why, why_size, "not a regular file (%s)", file_type(st.st_mode));
    else if (st.st_size > max)
        snprintf(why, why_size, "larger than %ld bytes", max);
    else
        text = read_fd(fd, st.st_size, max, len, why, why_size);
    return text;
}

char *lang_read_file(const char *path, size_t *len, char *why, size_t why_size)
{
    /* O_NONBLOCK: opening a FIFO must not wait for a writer */
    int fd = open(path, O_RDONLY | O_NONBLOCK | O_NOCTTY | O_CLOEXEC);
    if (fd < 0) {
        snprintf(why, why_size, "%s", strerror(errno));
        return NULL;
    }
    char *text = lang_read_fd(fd, CSG_PARSE_MAX_FILE, len, why, why_size);
    close(fd);
    return text;
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

/* .pov .inc .mcr .map (any case): a scene file, whose text may be quoted. */
static bool scene_like_name(const char *path)
{
    static const char *const ext[] = {".pov", ".inc", ".mcr", ".map"};
    size_t n = strlen(path);
    for (size_t i = 0; i < sizeof ext / sizeof ext[0]; i++)
        if (n > 4 && strcasecmp(path + n - 4, ext[i]) == 0)
            return true;
    return false;
}

/* Pushes the frame of a file (text in the arena) and reads on from it. */
static bool push_file(parser *p, const char *path, const char *canon, const char *text,
                      size_t len, csg_loc at)
{
    frame f;
    memset(&f, 0, sizeof f);
    f.kind = FRAME_FILE;
    csg_lexer_init(&f.lx, path, text, len);
    f.canon = canon;
    f.hidden = at.line > 0 && !scene_like_name(path);
    f.entered_at = at;
    f.cond_base = p->conds.count;
    if (at.line > 0 && !lang_scope_push(p))
        return false;
    f.scope = p->scopes.count - 1;
    return push_frame(p, &f);
}

bool lang_parse_main(parser *p, const char *path, const char *text, size_t len)
{
    const char *canon = canonical(p, path);
    const char *slash = strrchr(path, '/');
    p->main_dir = lang_strndup(p, path, slash ? (size_t)(slash - path + 1) : 0);
    csg_loc none = {path, 0, 0};
    if (!canon || !p->main_dir || !push_file(p, path, canon, text, len, none))
        return false;
    p->tok_ready = false;
    return lang_parse_statements(p);
}

/* ---- #include ----------------------------------------------------------------- */

/* dir + name, in the arena ("" dir: name as it is). */
static char *join(parser *p, const char *dir, size_t dirlen, const char *name)
{
    size_t n = strlen(name);
    bool slash = dirlen > 0 && dir[dirlen - 1] != '/';
    char *path = lang_alloc(p, dirlen + slash + n + 1);
    if (!path)
        return NULL;
    memcpy(path, dir, dirlen);
    if (slash)
        path[dirlen] = '/';
    memcpy(path + dirlen + slash, name, n);
    return path;
}

static bool exists(const char *path)
{
    struct stat st;
    return stat(path, &st) == 0;
}

/* The library folder i (the options' first, then the defaults); NULL past
 * the end. */
static const char *library(const parser *p, int i)
{
    if (i < p->opt.library_path_count)
        return p->opt.library_paths[i];
    return p->opt.no_default_library ? NULL : csg_default_library(i - p->opt.library_path_count);
}

/* Where `name` is: its first candidate that exists, else the first
 * candidate (whose reading then fails with its reason); *searched: library
 * folders were tried too. */
static char *find_include(parser *p, const char *name, bool *searched)
{
    *searched = false;
    if (name[0] == '/')
        return join(p, "", 0, name);
    const char *cur = lang_frame(p)->lx.file;
    const char *slash = strrchr(cur, '/');
    char *first = join(p, cur, slash ? (size_t)(slash - cur + 1) : 0, name);
    if (!first || exists(first))
        return first;
    char *path = join(p, p->main_dir, strlen(p->main_dir), name);
    if (path && exists(path))
        return path;
    for (int i = 0; (cur = library(p, i)) != NULL; i++) {
        *searched = true;
        path = join(p, cur, strlen(cur), name);
        if (path && exists(path))
            return path;
    }
    return first;
}

char *lang_find_file(parser *p, const char *name, bool *searched)
{
    return find_include(p, name, searched);
}

bool lang_file_exists(const char *path) { return exists(path); }

/* Whether `canon` may be opened by the #include at `at`: not too deep, not
 * a file being read already. */
static bool may_include(parser *p, csg_loc at, const char *path, const char *canon)
{
    if (p->include_depth >= CSG_PARSE_MAX_INCLUDE) {
        csg_error(p->d, at, "#include nested deeper than %d files", CSG_PARSE_MAX_INCLUDE);
        return false;
    }
    const frame *fr = p->frames.data;
    for (int i = 0; i < p->frames.count; i++) {
        if (fr[i].kind == FRAME_FILE && strcmp(fr[i].canon, canon) == 0) {
            csg_error(p->d, at, "#include cycle: '%s' is already being read", path);
            return false;
        }
    }
    return true;
}

/* The text of the included file, copied into the arena. */
static char *read_include(parser *p, csg_loc at, const char *path, bool searched, size_t *len)
{
    char why[256];
    char *text = lang_read_file(path, len, why, sizeof why);
    if (!text) {
        csg_error(p->d, at, "cannot read include file '%s': %s%s", path, why,
                  searched ? " (nor found in the library folders)" : "");
        return NULL;
    }
    char *copy = lang_strndup(p, text, *len);
    free(text);
    return copy;
}

static bool is_colors_inc(const char *name)
{
    return strcmp(name, "colors.inc") == 0;
}

/* #include of a file the scene wrote (fileio.c): its text as it is now,
 * named by its name, never a cycle with a file on disk. */
static bool include_written(parser *p, csg_loc at, const char *name, const char *data,
                            size_t len)
{
    size_t n = strlen(name);
    char *path = lang_strndup(p, name, n);
    char *canon = lang_alloc(p, n + sizeof "<written>/");
    char *text = lang_strndup(p, data, len);
    if (!path || !canon || !text)
        return false;
    memcpy(canon, "<written>/", sizeof "<written>/" - 1);
    memcpy(canon + sizeof "<written>/" - 1, name, n + 1);
    bool ok = may_include(p, at, path, canon) && push_file(p, path, canon, text, len, at);
    p->include_depth += ok;
    return ok;
}

bool lang_include(parser *p, csg_loc at)
{
    char *name = NULL;
    if (!lang_is_string_start(p))
        return lang_expected(p, "a file name in quotes expected after '#include'");
    if (!lang_parse_string(p, &name))
        return false;
    bool ok = false, searched = false;
    char *path = NULL;
    const char *written, *data;
    size_t written_len;
    if (name[0] == '\0') {
        csg_error(p->d, at, "#include: invalid file name");
    } else if (lang_written_find(p, name, &written, &data, &written_len)) {
        ok = include_written(p, at, written, data, written_len);
    } else if ((path = find_include(p, name, &searched)) != NULL) {
        if (is_colors_inc(name) && !exists(path)) {
            ok = lang_declare_builtin_colors(p);
        } else {
            const char *canon = canonical(p, path);
            size_t len = 0;
            const char *text = canon && may_include(p, at, path, canon)
                                   ? read_include(p, at, path, searched, &len) : NULL;
            if (text && p->opt.on_include)
                p->opt.on_include(p->opt.on_include_arg, path);
            ok = text && push_file(p, path, canon, text, len, at);
            p->include_depth += ok;
        }
    }
    free(name);
    return ok;
}
