/*
 * fileio.c — the scene's data files, read and written as POV-Ray 3.7 does
 * (Parse_Fopen, Parse_Fclose, Parse_Read, Parse_Read_Value, Parse_Write in
 * its source/backend/parser/tokenize.cpp):
 *
 *   #fopen NAME "file" read|write|append     #fclose NAME
 *   #read (NAME [,] VAR [,] VAR ...)          #write (NAME [,] ITEM [,] ITEM ...)
 *   file_exists("file")
 *
 * Where files are (csgtrace's rule, not POV-Ray's): a file name is
 * relative and stays inside its folder: no leading '/', no '..'
 * component (an error at the name).  Written files are kept in memory
 * (p->written) for the whole parse, so check, export and the ranks of an
 * MPI job write nothing; the scene carries them (csg_scene.written) and a
 * render writes them beside its output once the scene is read
 * (host/output/user_files.c).  A read looks in the written files first (a
 * file written can be read back, by #fopen or by #include, as POV-Ray's
 * makestacks.inc and meshmaker.inc do), then in the scene file's folder, opened
 * component by component without following a symbolic link (O_NOFOLLOW),
 * a regular file (O_NONBLOCK: a FIFO never blocks the open); the files
 * open for reading hold at most CSG_PARSE_MAX_DATA bytes together (each
 * reader has its own copy of a written file).
 *
 * The data format (POV-Ray's): values separated by commas, and comments;
 * POV-Ray 3.7 drops the token after a value whatever it is, so a value
 * not followed by a comma loses the next one, and so does csgtrace (3.8
 * fixed it; a file #write made has its commas where the scene put them).
 * A float is a number after optional signs (any '+', then at
 * most one '-'), a vector '<' 2 to 5 floats '>' (commas between them
 * optional; 4: a 4-vector, 5: a colour), a string a literal in double
 * quotes with the language's escapes.  #write prints a float as "%g", a
 * vector as "<%g,%g,...> " (with one trailing space), a string as it is.
 *
 * The end of a file: a #read that finds no value, or whose value is
 * followed by nothing but blanks, closes the file and removes NAME (so
 * `#while (defined(F)) #read (F, V) ... #end` sees every value once); the
 * names after it in that #read are left as they were.  A comma after the
 * last value makes the next #read find none (POV-Ray's behaviour, kept).
 *
 * Invariants: NAME holds (slot, generation) of an entry of p->user_files
 * (malloc'd entries: pointers stay valid while the vector grows); closing
 * bumps the entry's generation, so a copy of NAME (a macro argument) names
 * a closed file from then on, and the entry is reused.  A #read or #write
 * marks its file busy: a directive nested inside it (a macro call in an
 * argument) may not close, read or write that file.  At most
 * CSG_PARSE_MAX_OPEN_FILES files are open at once and the written files
 * hold at most CSG_PARSE_MAX_WRITTEN bytes together: a scene that writes
 * in an endless loop stops there, with that figure.
 */
#include <errno.h>
#include <fcntl.h>
#include <limits.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "parse_internal.h"

/* Distinct names written in one parse. */
#define MAX_WRITTEN_FILES 1024

/* A file #fopen opened. */
typedef struct {
    bool open;
    bool busy;          /* a #read or #write of it is running            */
    bool reading;       /* opened with read (else write or append)       */
    unsigned gen;       /* bumped when closed                            */
    char *name;         /* the name, normalised (malloc'd)               */
    char *shown;        /* reading: where it was read from, for messages */
    char *text;         /* reading: the whole file (malloc'd)            */
    size_t len;         /* reading: its bytes                            */
    csg_lexer lx;       /* reading: the next value                       */
    int out;            /* writing: its entry of p->written              */
} lang_user_file;

/* A file the scene wrote. */
typedef struct {
    char *name;         /* normalised (malloc'd)                         */
    char *data;         /* len bytes of cap (malloc'd)                   */
    size_t len, cap;
    bool append;        /* first opened with append                      */
} lang_written;

/* ---- names ----------------------------------------------------------------------- */

/* `given` normalised ('.' and empty components dropped) into malloc'd
 * memory; NULL with an error at `at` when it leaves its folder. */
static char *data_name(parser *p, const char *given, csg_loc at)
{
    size_t n = strlen(given);
    if (n == 0 || n > PATH_MAX) {
        csg_error(p->d, at, "invalid file name (%s)", n ? "too long" : "empty");
        return NULL;
    }
    if (given[0] == '/')
        goto outside;
    char *out = malloc(n + 1);
    if (!out) {
        lang_oom(p);
        return NULL;
    }
    size_t w = 0;
    for (const char *s = given; *s;) {
        size_t len = strcspn(s, "/");
        if (len == 2 && s[0] == '.' && s[1] == '.') {
            free(out);
            goto outside;
        }
        if (len > 0 && !(len == 1 && s[0] == '.')) {
            if (w)
                out[w++] = '/';
            memcpy(out + w, s, len);
            w += len;
        }
        s += len + (s[len] == '/');
    }
    out[w] = '\0';
    if (w == 0) {
        free(out);
        csg_error(p->d, at, "invalid file name '%s' (a folder)", given);
        return NULL;
    }
    return out;

outside:
    csg_error(p->d, at, "'%s' leaves the scene's folder: a scene reads and writes files only "
              "inside it (a relative name without '..')", given);
    return NULL;
}

/* The file `name` (normalised) of folder `dir` ("": the current one),
 * opened for reading without following a link anywhere on its path; -1
 * with the reason in why. */
static int open_beneath(const char *dir, const char *name, char *why, size_t why_size)
{
    int fd = open(dir[0] ? dir : ".", O_RDONLY | O_DIRECTORY | O_CLOEXEC);
    const char *s = name;
    for (size_t len; fd >= 0 && s[len = strcspn(s, "/")] == '/'; s += len + 1) {
        char part[NAME_MAX + 1];
        if (len > NAME_MAX) {
            close(fd);
            errno = ENAMETOOLONG;
            fd = -1;
            break;
        }
        memcpy(part, s, len);
        part[len] = '\0';
        int next = openat(fd, part, O_RDONLY | O_DIRECTORY | O_NOFOLLOW | O_CLOEXEC);
        close(fd);
        fd = next;
    }
    int file = fd < 0 ? -1 : openat(fd, s, O_RDONLY | O_NOFOLLOW | O_NONBLOCK | O_NOCTTY |
                                               O_CLOEXEC);
    int err = errno;
    if (fd >= 0)
        close(fd);
    if (file < 0)
        snprintf(why, why_size, "%s", err == ELOOP || err == ENOTDIR
                                          ? "a symbolic link on its path (a scene's files are "
                                            "read through none), or no folder"
                                          : strerror(err));
    return file;
}

/* The entry of p->written named `name`, or -1. */
static int written_find(parser *p, const char *name)
{
    const lang_written *w = p->written.data;
    for (int i = 0; i < p->written.count; i++)
        if (strcmp(w[i].name, name) == 0)
            return i;
    return -1;
}

/* ---- open files ------------------------------------------------------------------- */

static lang_user_file *file_at(parser *p, int slot)
{
    return ((lang_user_file **)p->user_files.data)[slot];
}

/* The open file datum d names, or NULL. */
static lang_user_file *file_of(parser *p, const datum *d)
{
    if (d->kind != SYM_FILE || d->u.file.slot < 0 || d->u.file.slot >= p->user_files.count)
        return NULL;
    lang_user_file *f = file_at(p, d->u.file.slot);
    return f->open && f->gen == d->u.file.gen ? f : NULL;
}

/* A closed entry to reuse, or a new one; -1 past the limit. */
static int file_slot(parser *p, csg_loc at)
{
    for (int i = 0; i < p->user_files.count; i++)
        if (!file_at(p, i)->open)
            return i;
    if (p->user_files.count >= CSG_PARSE_MAX_OPEN_FILES) {
        csg_error(p->d, at, "more than %d files open at once (#fclose them)",
                  CSG_PARSE_MAX_OPEN_FILES);
        return -1;
    }
    lang_user_file *f = calloc(1, sizeof *f);
    if (!f || !lang_vec_push(p, &p->user_files, sizeof f, &f)) {
        free(f);
        return p->d->failed ? -1 : (lang_oom(p), -1);
    }
    return p->user_files.count - 1;
}

/* Closes f, which `name` (len bytes) holds, and removes that name. */
static void file_close(parser *p, lang_user_file *f, const char *name, size_t len)
{
    symbol *sym = lang_sym_find(p, name, len);
    if (sym && file_of(p, &sym->d) == f)
        lang_sym_undef(p, name, len);
    free(f->name);
    free(f->shown);
    free(f->text);
    f->name = f->shown = f->text = NULL;
    p->reading_bytes -= f->reading ? f->len : 0;
    f->len = 0;
    f->open = false;
    f->gen++;
}

/* The open file that the current identifier names (consumed); NULL with
 * an error otherwise.  *name: its token. */
static lang_user_file *file_named(parser *p, const char *directive, csg_token *name)
{
    const csg_token *t = lang_tok_raw(p);
    if (t->kind != CSG_TOK_WORD || t->kw != CSG_KW_NONE) {
        char what[96];
        snprintf(what, sizeof what, "a file identifier expected in '%s'", directive);
        lang_expected(p, what);
        return NULL;
    }
    *name = *t;
    symbol *sym = lang_sym_find(p, t->text, t->len);
    lang_user_file *f = sym ? file_of(p, &sym->d) : NULL;
    int shown = (int)(t->len > 40 ? 40 : t->len);
    if (!f)
        csg_error(p->d, t->loc, "'%.*s' is not an open file (#fopen opens one; #fclose, or a "
                  "#read at its end, closes it)", shown, t->text);
    else if (f->busy)
        csg_error(p->d, t->loc, "'%.*s': a directive inside a #read or #write of a file may not "
                  "use that file", shown, t->text);
    return f && !f->busy && lang_next(p) ? f : NULL;
}

/* f (already reserved) opened for reading `name`: a written file's
 * current text, else the scene folder's file. */
static bool file_open_read(parser *p, lang_user_file *f, const char *name, csg_loc at)
{
    int w = written_find(p, name);
    size_t len = 0;
    if (w >= 0) {
        const lang_written *src = (const lang_written *)p->written.data + w;
        len = src->len;
        f->text = malloc(len + 1);
        f->shown = strdup(name);
        if (!f->text || !f->shown)
            return lang_oom(p);
        if (len)
            memcpy(f->text, src->data, len);
    } else {
        char why[160];
        int fd = open_beneath(p->main_dir, name, why, sizeof why);
        f->text = fd < 0 ? NULL : lang_read_fd(fd, CSG_PARSE_MAX_DATA, &len, why, sizeof why);
        if (fd >= 0)
            close(fd);
        if (!f->text) {
            csg_error(p->d, at, "#fopen: cannot read '%s' in the scene's folder: %s", name, why);
            return false;
        }
        size_t dir = strlen(p->main_dir);
        f->shown = malloc(dir + strlen(name) + 1);
        if (!f->shown)
            return lang_oom(p);
        memcpy(f->shown, p->main_dir, dir);
        strcpy(f->shown + dir, name);
    }
    if (len > (size_t)CSG_PARSE_MAX_DATA - p->reading_bytes) {
        csg_error(p->d, at, "#fopen: the files open for reading would hold more than %ld bytes "
                  "together", CSG_PARSE_MAX_DATA);
        return false;
    }
    p->reading_bytes += len;
    f->len = len;
    f->text[len] = '\0';
    csg_lexer_init(&f->lx, f->shown, f->text, len);
    f->reading = true;
    return true;
}

/* f (already reserved) opened for writing `name`: its entry of the
 * written files, emptied unless `append`. */
static bool file_open_write(parser *p, lang_user_file *f, const char *name, bool append,
                            csg_loc at)
{
    int w = written_find(p, name);
    if (w < 0) {
        if (p->written.count >= MAX_WRITTEN_FILES) {
            csg_error(p->d, at, "more than %d files written by one scene", MAX_WRITTEN_FILES);
            return false;
        }
        lang_written entry = {strdup(name), NULL, 0, 0, append};
        if (!entry.name || !lang_vec_push(p, &p->written, sizeof entry, &entry)) {
            free(entry.name);
            return p->d->failed ? false : lang_oom(p);
        }
        w = p->written.count - 1;
    } else if (!append) {
        lang_written *entry = (lang_written *)p->written.data + w;
        p->written_bytes -= entry->len;
        entry->len = 0;
        entry->append = false;
    }
    f->out = w;
    f->reading = false;
    return true;
}

/* The mode word after the file name: 0 read, 1 write, 2 append, -1 none. */
static int open_mode(const csg_token *t)
{
    static const char *const modes[] = {"read", "write", "append"};
    for (int i = 0; i < 3 && t->kind == CSG_TOK_WORD; i++)
        if (t->len == strlen(modes[i]) && memcmp(t->text, modes[i], t->len) == 0)
            return i;
    return -1;
}

bool lang_fopen(parser *p, csg_loc at)
{
    (void)at;
    const csg_token *t = lang_tok_raw(p);
    if (t->kind != CSG_TOK_WORD || t->kw != CSG_KW_NONE)
        return lang_expected(p, "a new identifier expected after '#fopen'");
    csg_token id = *t;
    symbol *old = lang_sym_find(p, t->text, t->len);
    if (old) { /* POV-Ray's GET(IDENTIFIER_TOKEN): a name not in use */
        csg_error(p->d, t->loc, "'%.*s' is already %s: #fopen needs a name not in use (#fclose "
                  "or #undef it first)", (int)(t->len > 40 ? 40 : t->len), t->text,
                  lang_kind_name(&old->d));
        return false;
    }
    if (!lang_next(p))
        return false;
    if (!lang_is_string_start(p))
        return lang_expected(p, "a file name in quotes expected after '#fopen NAME'");
    csg_loc name_at = lang_tok(p)->loc;
    char *given = NULL, *name = NULL;
    if (!lang_parse_string(p, &given))
        return false;
    name = data_name(p, given, name_at);
    free(given);
    if (!name)
        return false;
    int mode = open_mode(lang_tok_raw(p));
    int slot = -1;
    bool ok = false;
    if (mode < 0)
        lang_expected(p, "'read', 'write' or 'append' expected after the file name of '#fopen'");
    else if (lang_next(p) && (slot = file_slot(p, id.loc)) >= 0) {
        lang_user_file *f = file_at(p, slot);
        ok = mode == 0 ? file_open_read(p, f, name, name_at)
                       : file_open_write(p, f, name, mode == 2, name_at);
        if (ok) {
            f->name = name;
            name = NULL;
            f->open = true;
        } else {
            free(f->shown);
            free(f->text);
            f->shown = f->text = NULL;
        }
    }
    free(name);
    symbol *sym = ok ? lang_sym_declare(p, id.text, id.len, id.loc) : NULL;
    if (!sym) {
        if (ok)
            file_close(p, file_at(p, slot), id.text, id.len);
        return false;
    }
    datum d;
    memset(&d, 0, sizeof d);
    d.kind = SYM_FILE;
    d.u.file.slot = slot;
    d.u.file.gen = file_at(p, slot)->gen;
    lang_sym_assign(sym, &d);
    return true;
}

/* #fclose NAME: closes the file NAME holds; a name that holds none (a
 * file closed already, at its end) is accepted, as POV-Ray does. */
bool lang_fclose(parser *p, csg_loc at)
{
    (void)at;
    const csg_token *t = lang_tok_raw(p);
    if (t->kind != CSG_TOK_WORD || t->kw != CSG_KW_NONE)
        return lang_expected(p, "an identifier expected after '#fclose'");
    csg_token name = *t;
    symbol *sym = lang_sym_find(p, t->text, t->len);
    lang_user_file *f = sym ? file_of(p, &sym->d) : NULL;
    if (f && f->busy) {
        csg_error(p->d, t->loc, "'%.*s': a directive inside a #read or #write of a file may not "
                  "close that file", (int)(t->len > 40 ? 40 : t->len), t->text);
        return false;
    }
    if (!lang_next(p))
        return false;
    if (f)
        file_close(p, f, name.text, name.len);
    return true;
}

/* ---- #read -------------------------------------------------------------------------- */

static bool data_token(parser *p, lang_user_file *f, csg_token *t)
{
    return csg_lexer_next(&f->lx, t, p->d);
}

static bool data_expected(parser *p, const csg_token *t, const char *what)
{
    char got[64];
    csg_token_describe(t, got, sizeof got);
    csg_error(p->d, t->loc, "%s in the data file, got %s", what, got);
    return false;
}

static bool is_punct(const csg_token *t, int c)
{
    return t->kind == CSG_TOK_PUNCT && t->punct == c;
}

static bool is_float_start(const csg_token *t)
{
    return t->kind == CSG_TOK_NUMBER || is_punct(t, '+') || is_punct(t, '-');
}

/* A signed float whose first token *t was read (POV-Ray's
 * Parse_Signed_Float: any '+', then at most one '-', then a number). */
static bool data_float(parser *p, lang_user_file *f, csg_token *t, double *out)
{
    double sign = 1.0;
    while (is_punct(t, '+'))
        if (!data_token(p, f, t))
            return false;
    if (is_punct(t, '-')) {
        sign = -1.0;
        if (!data_token(p, f, t))
            return false;
    }
    if (t->kind != CSG_TOK_NUMBER)
        return data_expected(p, t, "a number expected");
    *out = sign * t->number;
    return true;
}

/* Skips a ',' if one comes next; *after: the token after the value (EOF
 * at the end of the file). */
static bool data_comma(parser *p, lang_user_file *f, csg_token *after)
{
    csg_lexer mark = f->lx;
    if (!data_token(p, f, after))
        return false;
    if (!is_punct(after, ','))
        f->lx = mark;
    return true;
}

/* The components of a vector after its '<', up to its '>'. */
static bool data_vector(parser *p, lang_user_file *f, value *v)
{
    v->dim = 0;
    for (;;) {
        csg_token t;
        if (!data_token(p, f, &t))
            return false;
        if (is_punct(&t, '>') && v->dim >= 2)
            return true;
        if (!is_float_start(&t))
            return data_expected(p, &t, v->dim < 2 ? "a number expected (a vector has 2 to 5 "
                                                     "components)" : "a number or '>' expected");
        if (v->dim == 5) {
            csg_error(p->d, t.loc, "a vector of more than 5 components in the data file");
            return false;
        }
        if (!data_float(p, f, &t, &v->v[v->dim++]) || !data_comma(p, f, &t))
            return false;
    }
}

/* The next value of f into *out (*got); *end: the file has no more. */
static bool read_value(parser *p, lang_user_file *f, datum *out, bool *got, bool *end)
{
    csg_token t;
    memset(out, 0, sizeof *out);
    *got = false;
    if (!data_token(p, f, &t))
        return false;
    if (t.kind == CSG_TOK_EOF) {
        *end = true;
        return true;
    }
    if (t.kind == CSG_TOK_STRING) {
        out->kind = SYM_STRING;
        if (!(out->u.str = lang_string_literal(p, &t))) {
            out->kind = SYM_VALUE;
            return false;
        }
    } else if (is_punct(&t, '<')) {
        out->kind = SYM_VALUE;
        if (!data_vector(p, f, &out->u.val))
            return false;
    } else if (is_float_start(&t)) {
        out->kind = SYM_VALUE;
        out->u.val.dim = 1;
        if (!data_float(p, f, &t, &out->u.val.v[0]))
            return false;
    } else {
        return data_expected(p, &t, "a float, vector or string expected");
    }
    /* POV-Ray 3.7 reads the token after a value and keeps it only when it
     * is the end: a comma is skipped, and so is anything else (its
     * Parse_Read_Value clears the token it ungot) */
    csg_token after;
    if (!data_token(p, f, &after)) {
        lang_datum_free(out);
        return false;
    }
    *got = true;
    *end = after.kind == CSG_TOK_EOF; /* (POV-Ray: the end right after a value ends the file) */
    return true;
}

/* One VAR of #read: the current identifier; it gets the next value
 * unless the file ended. */
static bool read_into(parser *p, lang_user_file *f, bool *end)
{
    const csg_token *t = lang_tok_raw(p);
    if (t->kind != CSG_TOK_WORD || t->kw != CSG_KW_NONE)
        return lang_expected(p, "a name to read into, or ')', expected in '#read'");
    csg_token name = *t;
    symbol *sym = lang_sym_find(p, t->text, t->len);
    /* POV-Ray 3.7 reads into a new name, a float, a 3-vector or a string
     * (a 2-, 4- or 5-component one is refused: its Parse_Read) */
    if (sym && sym->d.kind != SYM_STRING &&
        (sym->d.kind != SYM_VALUE || (sym->d.u.val.dim != 1 && sym->d.u.val.dim != 3))) {
        const char *kind = sym->d.kind == SYM_VALUE ? lang_dim_name(sym->d.u.val.dim)
                                                    : lang_kind_name(&sym->d);
        csg_error(p->d, t->loc, "'%.*s' is %s: #read sets a new name, a float, a 3-vector or a "
                  "string (as POV-Ray 3.7)", (int)(t->len > 40 ? 40 : t->len), t->text, kind);
        return false;
    }
    if (!lang_next(p))
        return false;
    if (*end)
        return true;
    datum v;
    bool got;
    if (!read_value(p, f, &v, &got, end))
        return false;
    if (got) { /* as #declare: the innermost binding, else a new global one */
        sym = lang_sym_declare(p, name.text, name.len, name.loc);
        if (!sym) {
            lang_datum_free(&v);
            return false;
        }
        lang_sym_assign(sym, &v);
    }
    return !lang_is_punct(p, ',') || lang_next(p);
}

bool lang_read(parser *p, csg_loc at)
{
    (void)at;
    csg_token name;
    lang_user_file *f;
    if (!lang_expect_punct(p, '(', "after '#read'") || !(f = file_named(p, "#read", &name)))
        return false;
    if (!f->reading) {
        csg_error(p->d, name.loc, "'%.*s' is open for writing: #read needs a file opened with "
                  "'read'", (int)(name.len > 40 ? 40 : name.len), name.text);
        return false;
    }
    if (lang_is_punct(p, ',') && !lang_next(p))
        return false;
    f->busy = true;
    bool end = false, ok = true;
    while (ok && !lang_is_punct(p, ')')) {
        if (end && lang_is_punct(p, ',')) /* (after the end: names only, commas ignored) */
            ok = lang_next(p);
        else
            ok = read_into(p, f, &end);
    }
    f->busy = false;
    ok = ok && lang_next(p);
    if (ok && end)
        file_close(p, f, name.text, name.len);
    return ok;
}

/* ---- #write ---------------------------------------------------------------------------- */

/* n bytes more in f's written file. */
static bool write_bytes(parser *p, lang_user_file *f, const char *s, size_t n, csg_loc at)
{
    lang_written *w = (lang_written *)p->written.data + f->out;
    if (n == 0) /* (an empty string: nothing, and no data yet perhaps) */
        return true;
    if (n > (size_t)CSG_PARSE_MAX_WRITTEN - p->written_bytes) {
        csg_error(p->d, at, "#write: the files this scene writes would hold more than %ld bytes "
                  "together (csgtrace keeps them in memory while it reads the scene)",
                  CSG_PARSE_MAX_WRITTEN);
        return false;
    }
    if (w->len + n > w->cap) {
        size_t cap = w->cap ? w->cap : 256;
        while (cap < w->len + n)
            cap *= 2;
        char *data = realloc(w->data, cap);
        if (!data)
            return lang_oom(p);
        w->data = data;
        w->cap = cap;
    }
    memcpy(w->data + w->len, s, n);
    w->len += n;
    p->written_bytes += n;
    return true;
}

/* A float as "%g", a vector as "<%g,%g,...> " (POV-Ray's Parse_Write). */
static bool write_value(parser *p, lang_user_file *f, const value *v, csg_loc at)
{
    char buf[5 * 32 + 8];
    size_t n = 0;
    if (v->dim == 1)
        return write_bytes(p, f, buf, (size_t)snprintf(buf, sizeof buf, "%g", v->v[0]), at);
    buf[n++] = '<';
    for (int i = 0; i < v->dim; i++)
        n += (size_t)snprintf(buf + n, sizeof buf - n, i ? ",%g" : "%g", v->v[i]);
    n += (size_t)snprintf(buf + n, sizeof buf - n, "> ");
    return write_bytes(p, f, buf, n, at);
}

/* One ITEM of #write: a string, or a float or vector expression. */
static bool write_item(parser *p, lang_user_file *f)
{
    csg_loc at = lang_tok(p)->loc;
    if (lang_is_string_start(p)) {
        char *s = NULL;
        bool ok = lang_parse_string(p, &s) && write_bytes(p, f, s, strlen(s), at);
        free(s);
        return ok;
    }
    value v; /* (a colour keyword is no ITEM: POV-Ray 3.7 expects a string there) */
    if (!lang_is_expr_start(p))
        return lang_expected(p, "a string, an expression or ')' expected in '#write'");
    return lang_parse_full_expr(p, &v) && write_value(p, f, &v, at);
}

bool lang_write(parser *p, csg_loc at)
{
    (void)at;
    csg_token name;
    lang_user_file *f;
    if (!lang_expect_punct(p, '(', "after '#write'") || !(f = file_named(p, "#write", &name)))
        return false;
    if (f->reading) {
        csg_error(p->d, name.loc, "'%.*s' is open for reading: #write needs a file opened with "
                  "'write' or 'append'", (int)(name.len > 40 ? 40 : name.len), name.text);
        return false;
    }
    f->busy = true;
    bool ok = true;
    while (ok && !lang_is_punct(p, ')'))
        ok = lang_is_punct(p, ',') ? lang_next(p) : write_item(p, f);
    f->busy = false;
    return ok && lang_next(p);
}

/* ---- #include of a written file ---------------------------------------------------------- */

bool lang_written_find(parser *p, const char *given, const char **name, const char **data,
                       size_t *len)
{
    if (given[0] == '/' || strstr(given, "..")) /* (the include rules apply) */
        return false;
    for (int i = 0; i < p->written.count; i++) {
        const lang_written *w = (const lang_written *)p->written.data + i;
        const char *a = given, *b = w->name;
        while (a[0] == '.' && a[1] == '/') /* ("./x.inc" is "x.inc") */
            a += 2;
        if (strcmp(a, b) == 0) {
            *name = w->name;
            *data = w->data ? w->data : "";
            *len = w->len;
            return true;
        }
    }
    return false;
}

/* ---- file_exists ------------------------------------------------------------------------ */

bool lang_parse_file_exists(parser *p, double *out)
{
    if (!lang_next(p))
        return false;
    csg_loc open = lang_tok(p)->loc;
    if (!lang_expect_punct(p, '(', "after 'file_exists'"))
        return false;
    if (!lang_is_string_start(p))
        return lang_expected(p, "a file name expected in 'file_exists'");
    csg_loc name_at = lang_tok(p)->loc;
    char *given = NULL;
    if (!lang_parse_string(p, &given))
        return false;
    char *name = data_name(p, given, name_at);
    free(given);
    if (!name)
        return false;
    bool found = written_find(p, name) >= 0;
    if (!found) {
        char why[160];
        int fd = open_beneath(p->main_dir, name, why, sizeof why);
        struct stat st;
        found = fd >= 0 && fstat(fd, &st) == 0 && S_ISREG(st.st_mode);
        if (fd >= 0)
            close(fd);
    }
    free(name);
    *out = found;
    if (!lang_is_punct(p, ')'))
        return lang_expected_close(p, ')', "(", open);
    return lang_next(p);
}

/* ---- the end of the parse ---------------------------------------------------------------- */

bool lang_files_to_scene(parser *p)
{
    csg_scene *s = p->s;
    int n = p->written.count;
    if (n == 0)
        return true;
    csg_written_file *out = lang_alloc(p, (size_t)n * sizeof *out);
    if (!out)
        return false;
    lang_written *w = p->written.data;
    for (int i = 0; i < n; i++) {
        if (!csg_arena_adopt(s->arena, w[i].name))
            return lang_oom(p);
        out[i].name = w[i].name;
        w[i].name = NULL;
        out[i].data = "";
        if (w[i].data) {
            if (!csg_arena_adopt(s->arena, w[i].data))
                return lang_oom(p);
            out[i].data = w[i].data;
            w[i].data = NULL;
        }
        out[i].len = w[i].len;
        out[i].append = w[i].append;
    }
    s->written = out;
    s->written_count = n;
    return true;
}

void lang_files_free(parser *p)
{
    for (int i = 0; i < p->user_files.count; i++) {
        lang_user_file *f = file_at(p, i);
        free(f->name);
        free(f->shown);
        free(f->text);
        free(f);
    }
    lang_written *w = p->written.data;
    for (int i = 0; i < p->written.count; i++) {
        free(w[i].name);
        free(w[i].data);
    }
    free(p->user_files.data);
    free(p->written.data);
    p->user_files.data = p->written.data = NULL;
    p->user_files.count = p->written.count = 0;
}
