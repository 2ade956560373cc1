/*
 * parse_internal.h — what the files of the scene-language front end share;
 * internal to csg/lang (the rest of csgtrace sees parser.h only).
 *
 *   parser.c   the statement and object grammar, the parse's memory, the
 *              end of the parse and the entry points csg_parse_*
 *   expr.c     values and expressions (expr.h)
 *   symbols.c  the symbol table of #declare
 *   source.c   files, #include, the lexer of the file being read, and the
 *              messages about the current token
 *
 * One parse state, `parser`, is passed by pointer to every function; its
 * fields are grouped by the file that owns them.  Names shared across the
 * files carry the prefix lang_; everything else is static.
 *
 * Errors: a function that fails writes the message into p->d (the first
 * error wins) and returns false or NULL; every caller then returns at once.
 */
#ifndef CSG_LANG_PARSE_INTERNAL_H
#define CSG_LANG_PARSE_INTERNAL_H

#include <stdbool.h>
#include <stddef.h>

#include "expr.h"
#include "lexer.h"
#include "parser.h"

/* A growable malloc'd array. */
typedef struct {
    void *data;
    int count, cap;
} vec;

enum sym_kind { SYM_VALUE, SYM_PIGMENT, SYM_FINISH, SYM_TEXTURE, SYM_INTERIOR, SYM_OBJECT };

typedef struct {
    const char *name; /* arena copy, len bytes */
    size_t len;
    enum sym_kind kind;
    value val;
    csg_pigment pigment;
    csg_finish finish;
    csg_texture texture;
    csg_interior interior;
    csg_object *object; /* a tree that is never in the scene: used by copy */
} symbol;

typedef struct parser parser;

struct parser {
    csg_scene *s;       /* the scene being built                           */
    csg_diag *d;        /* the message of the first error                  */
    /* source.c: the token stream */
    csg_lexer lx;       /* the file being read                             */
    csg_token tok;      /* the current token (one of lookahead)            */
    int nesting;        /* objects, parentheses and vector literals open
                           around the current token; <= CSG_PARSE_MAX_NESTING */
    int include_depth;  /* files open around the current one               */
    const char *include_stack[CSG_PARSE_MAX_INCLUDE + 1]; /* real paths    */
    /* symbols.c */
    symbol **syms;      /* open addressing hash table, sym_cap a power of 2 */
    size_t sym_cap, sym_count;
    /* parser.c: tables copied into the scene's arena at the end */
    vec textures;       /* csg_texture                                     */
    vec interiors;      /* csg_interior                                    */
    vec lights;         /* csg_light                                       */
    vec objects;        /* csg_object *: the top-level objects             */
    vec stack;          /* csg_object *: children of the open CSG objects  */
    long nodes;         /* tree nodes created, <= CSG_PARSE_MAX_OBJECTS    */
};

/* ---- tokens: the one token of lookahead (inline: used on every token) ---- */

/* Reads the next token of the current file into p->tok. */
static inline bool lang_next(parser *p)
{
    return csg_lexer_next(&p->lx, &p->tok, p->d);
}

static inline bool lang_is_punct(const parser *p, char c)
{
    return p->tok.kind == CSG_TOK_PUNCT && p->tok.punct == c;
}

static inline bool lang_is_kw(const parser *p, enum csg_kw kw)
{
    return p->tok.kind == CSG_TOK_WORD && p->tok.kw == kw;
}

static inline bool lang_is_ident(const parser *p)
{
    return p->tok.kind == CSG_TOK_WORD && p->tok.kw == CSG_KW_NONE;
}

/* ---- parser.c: memory, statements ------------------------------------------ */

/* "out of memory"; returns false. */
bool lang_oom(parser *p);
/* Arena memory that lives as long as the scene (NULL: out of memory). */
void *lang_alloc(parser *p, size_t size);
char *lang_strndup(parser *p, const char *text, size_t len);
/* Statements up to the end of the current file. */
bool lang_parse_statements(parser *p);

/* ---- source.c: messages, nesting, files ------------------------------------ */

/* "<what expected ...>, got <token>" — or the unsupported-word message. */
bool lang_expected(parser *p, const char *what);
/* "'}' expected (to close 'union' at 12:3), got 'sphere'" */
bool lang_expected_close(parser *p, char closer, const char *opener, csg_loc at);
/* Consumes "{" after the keyword `name`. */
bool lang_expect_open(parser *p, const char *name);
/* Consumes the ';' that ends the directive '#directive' at `at`. */
bool lang_expect_semicolon(parser *p, const char *directive, csg_loc at);
/* One more (enter) or one less (leave) level of nesting at `loc`. */
bool lang_enter(parser *p, csg_loc loc);
void lang_leave(parser *p);

/* Reads a whole file into malloc'd memory (*err: errno on failure). */
char *lang_read_file(const char *path, size_t *len, int *err);
/* Reads the top file: its name `path` and its `text` are in the arena. */
bool lang_parse_main(parser *p, const char *path, const char *text, size_t len);
/* #include "file"; the current token is the directive. */
bool lang_parse_include(parser *p);

/* ---- symbols.c: the symbol table -------------------------------------------- */

/* The declared symbol named by the current identifier, of kind `want`
 * (want_name for the message); consumes the identifier. */
bool lang_lookup(parser *p, enum sym_kind want, const char *want_name, symbol **out);
/* The current identifier's symbol when it is declared with kind `kind`. */
symbol *lang_peek_sym(const parser *p, enum sym_kind kind);
/* Declares `name` (len bytes) as *def (its name fields are ignored). */
bool lang_sym_set(parser *p, const char *name, size_t len, const symbol *def);
/* #include "colors.inc": every built-in colour (colors.c) as a symbol. */
bool lang_declare_builtin_colors(parser *p);
void lang_symbols_free(parser *p);

#endif
