/*
 * parse_internal.h — what the files of the scene-language front end share;
 * internal to csg/lang (the rest of csgtrace sees parser.h only).
 *
 *   source.c      files, #include, the input frames (files and macro
 *                 bodies), the current token and its lazy reading, the
 *                 messages about the current token
 *   directives.c  #if #while #for #switch #macro ... : the directives the
 *                 token layer runs wherever they appear, macro calls
 *   declare.c     #declare / #local / #undef / #default, right-hand values
 *                 (rvalues), arrays, declarations that use unsupported
 *                 constructs (kept, and reported only when used)
 *   symbols.c     scopes and symbols
 *   expr.c        numeric expressions (expr.h), builtins.c its functions,
 *                 strings.c string expressions
 *   texture.c     pigment, colour map, finish, texture, interior
 *   fileio.c      #fopen #fclose #read #write, file_exists(): the scene's
 *                 data files (read from its folder, written in memory)
 *   parser.c      the statement and object grammar, the parse's memory, the
 *                 end of the parse and the entry points csg_parse_*
 *
 * One parse state, `parser`, is passed by pointer to every function; its
 * fields are grouped by the file that owns them.  Names shared across the
 * files carry the prefix lang_; everything else is static.
 *
 * The token layer (POV-Ray's model): directives and macro calls are handled
 * when a token is read, wherever they are, so the grammar never sees them.
 * The current token is read lazily: lang_next only consumes it, and the
 * next one is read (and its directives run) when someone looks at it
 * (lang_tok).  So a directive handler that ends by checking for an optional
 * token leaves the directive after it unread, and a run of directives is
 * handled by a loop, not by recursion.
 *
 * Errors: a function that fails writes the message into p->d (the first
 * error wins) and returns false or NULL; every caller then returns at once.
 * After an error the current token is CSG_TOK_ERROR, which matches nothing.
 */
#ifndef CSG_LANG_PARSE_INTERNAL_H
#define CSG_LANG_PARSE_INTERNAL_H

#include <stdbool.h>
#include <stddef.h>
#include <stdio.h>

#include "expr.h"
#include "lexer.h"
#include "parser.h"

/* A growable malloc'd array. */
typedef struct {
    void *data;
    int count, cap;
} vec;

/* ---- values a name can hold -------------------------------------------------- */

enum sym_kind {
    SYM_VALUE,      /* float, vector or colour                         */
    SYM_STRING,
    SYM_PIGMENT,
    SYM_FINISH,
    SYM_TEXTURE,
    SYM_INTERIOR,
    SYM_NORMAL,
    SYM_MATERIAL,
    SYM_OBJECT,
    SYM_COLOR_MAP,
    SYM_CAMERA,
    SYM_SKY,
    SYM_TRANSFORM,
    SYM_ARRAY,
    SYM_MACRO,
    SYM_FILE,       /* a file #fopen opened (fileio.c)                 */
    SYM_UNSUPPORTED /* a declaration that used an unsupported construct */
};

typedef struct lang_array lang_array;
typedef struct lang_macro lang_macro;
typedef struct lang_unusable lang_unusable;

/* material { texture { } interior { } }: what it gives an object. */
typedef struct {
    bool has_texture, has_interior;
    csg_texture texture;
    csg_interior interior;
} lang_material;

/* A colour map, in the arena; never written once made. */
typedef struct {
    int count;
    const csg_map_entry *entries;
} lang_color_map;

/* What a name, an array element or a macro argument holds. */
typedef struct {
    enum sym_kind kind;
    union {
        value val;
        char *str;                 /* malloc'd, NUL-terminated, owned        */
        csg_pigment pigment;
        csg_finish finish;
        csg_texture texture;
        csg_interior interior;
        csg_normal normal;
        const lang_material *material; /* arena                              */
        csg_object *object;        /* a tree never in the scene: copied at use */
        lang_color_map cmap;
        csg_camera_src camera;
        const csg_sky *sky;        /* arena                                  */
        csg_xform transform;       /* object -> world, as a step composes it */
        lang_array *array;         /* malloc'd, owned                        */
        const lang_macro *macro;   /* arena                                  */
        const lang_unusable *why; /* arena                                */
        struct {
            int slot;              /* its entry of p->user_files             */
            unsigned gen;          /* the entry's generation when opened: an
                                      older one names a file closed since   */
        } file;
    } u;
} datum;

/* array[d0][d1]...: at most 5 dimensions, elements set one by one. */
struct lang_array {
    int dims;
    int size[5];
    long total;
    enum sym_kind type;  /* the kind of the first element set; SYM_UNSUPPORTED:
                            none set yet                                     */
    datum **elems;       /* total entries, NULL until set (malloc'd each)    */
};

/* #macro NAME(P1, P2, ...) body #end: the body is re-read from its file's
 * text (which the arena keeps) at every call. */
#define LANG_MAX_PARAMS 56 /* POV-Ray's limit */
struct lang_macro {
    const char *name;
    csg_loc at;              /* the #macro directive                       */
    csg_lexer body;          /* a lexer at the body's start, ending at its #end */
    int param_count;
    const char *params[LANG_MAX_PARAMS];
};

/* Why a declared name cannot be used: the construct, where it was met
 * and the declaration that met it. */
struct lang_unusable {
    const char *construct;   /* "'normal'", "'#fopen'", ...                */
    csg_loc construct_at;
    const char *name;        /* the declared name                          */
    csg_loc declared_at;
};

typedef struct symbol symbol;

/* A name of the symbol table and its innermost binding (NULL: none now). */
struct lang_name {
    char *name;              /* malloc'd, len bytes; NULL: an empty slot    */
    size_t len;
    symbol *top;
};

struct symbol {
    const char *name;        /* its lang_name's copy, len bytes            */
    size_t len;
    datum d;
    int scope;               /* 0: global                                  */
    symbol *shadowed;        /* the binding of the same name it hides      */
    symbol *next_in_scope;   /* the symbols of its scope, newest first     */
    csg_loc declared_at;
    symbol *ref;             /* a macro parameter given a lone identifier:
                                the caller's binding it stands for (POV-Ray
                                passes it by reference: the lookups and the
                                assignments of the name reach that one);
                                NULL: a value of its own                    */
};

/* ---- the input: frames and conditionals ---------------------------------------- */

enum frame_kind { FRAME_FILE, FRAME_MACRO };

/* A place tokens are read from: a file, or the body of a macro call. */
typedef struct {
    enum frame_kind kind;
    csg_lexer lx;            /* the reading position                       */
    const char *canon;       /* FILE: canonical path (cycle detection)     */
    bool hidden;             /* FILE: not a scene file: never quoted       */
    csg_loc entered_at;      /* the #include or the macro call (line 0: the
                                scene file itself)                         */
    const char *macro;       /* MACRO: its name                            */
    int cond_base;           /* conds open when the frame was entered      */
    int scope;               /* the scope the frame opened (FILE main: 0)  */
} frame;

enum cond_kind {
    COND_IF,      /* a branch of #if / #ifdef / #ifndef / #else being run   */
    COND_WHILE,   /* the body of a #while being run                         */
    COND_FOR,     /* the body of a #for being run                           */
    COND_SWITCH   /* the cases of a #switch being run (after a match)       */
};

/* An open directive block. */
typedef struct {
    enum cond_kind kind;
    csg_loc at;              /* the directive that opened it               */
    int frame;               /* the frame it was opened in                 */
    bool in_else;            /* COND_IF: the #else branch                  */
    csg_lexer restart;       /* WHILE: before its condition; FOR: after its
                                header                                      */
    const char *var;         /* FOR: the loop variable (arena)             */
    double end, step;        /* FOR                                        */
} cond;

/* ---- the parse state ------------------------------------------------------------- */

typedef struct parser parser;

struct parser {
    csg_scene *s;       /* the scene being built                           */
    csg_diag *d;        /* the message of the first error                  */
    csg_parse_options opt; /* as given, defaults filled in                 */
    /* source.c: the token stream */
    vec frames;         /* frame: the input being read, innermost last      */
    csg_token tok;      /* the current token                               */
    bool tok_ready;     /* false: consumed, the next one is still unread    */
    bool tok_raw;       /* true: read but its directives not run yet        */
    int nesting;        /* objects, parentheses, vector literals and
                           directives open around the current token;
                           <= CSG_PARSE_MAX_NESTING                         */
    int include_depth;  /* files open around the main one                  */
    int macro_depth;    /* macro calls open                                */
    long tokens;        /* raw tokens read, <= opt.max_tokens              */
    const char *main_dir; /* the scene file's directory (arena), "" none   */
    /* directives.c */
    vec conds;          /* cond: open directive blocks                      */
    double version;     /* #version (3.7 until set)                         */
    csg_loc transform_at; /* texture.c: the last transform keyword read    */
    /* declare.c: an unsupported construct met while declaring */
    bool unsupported;   /* the error in d is about an unsupported construct */
    lang_unusable why; /* ... which one and where                       */
    csg_texture default_texture; /* #default { texture / pigment / finish } */
    /* builtins.c: seed() streams */
    vec rand_streams;   /* unsigned int                                     */
    /* symbols.c */
    struct lang_name *names; /* open addressing hash of every name ever
                           bound, with its innermost binding               */
    size_t name_cap, name_used;
    vec scopes;         /* symbol *: the newest symbol of each open scope   */
    /* parser.c: tables copied into the scene's arena at the end */
    vec textures;       /* csg_texture                                     */
    vec interiors;      /* csg_interior                                    */
    vec lights;         /* csg_light                                       */
    vec objects;        /* csg_object *: the top-level objects             */
    vec stack;          /* csg_object *: children of the open CSG objects  */
    long nodes;         /* tree nodes created, <= CSG_PARSE_MAX_OBJECTS    */
    int default_entry;  /* the textures entry of the default texture last
                           given to a top-level object (-1: none)           */
    /* fileio.c */
    vec user_files;     /* lang_user_file: files #fopen opened (a closed
                           entry is reused)                                 */
    vec written;        /* lang_written: the files the scene wrote          */
    size_t written_bytes; /* their bytes, <= CSG_PARSE_MAX_WRITTEN          */
    size_t reading_bytes; /* the texts of the files open for reading,
                           <= CSG_PARSE_MAX_DATA                            */
};

/* ---- source.c: tokens -------------------------------------------------------------- */

/* lang_tok when the current token is not resolved yet (or after an error). */
const csg_token *lang_tok_read(parser *p);

/* The current token, its directives and macro calls run (CSG_TOK_ERROR
 * after an error).  Inline: a grammar rule asks for the same token several
 * times (is it '}'? a transform? pigment? ...), 10^7 calls for an 8 MB
 * scene, and all but the first find it resolved. */
static inline const csg_token *lang_tok(parser *p)
{
    if (p->tok_ready && !p->tok_raw && !p->d->failed)
        return &p->tok;
    return lang_tok_read(p);
}
/* The current token as read, without running a directive or a macro call
 * it may be (for names: #declare NAME, #undef NAME, #macro NAME, ...). */
const csg_token *lang_tok_raw(parser *p);
/* Consumes the current token; false once an error has been reported. */
bool lang_next(parser *p);

static inline bool lang_is_punct(parser *p, int c)
{
    const csg_token *t = lang_tok(p);
    return t->kind == CSG_TOK_PUNCT && t->punct == c;
}

static inline bool lang_is_kw(parser *p, enum csg_kw kw)
{
    const csg_token *t = lang_tok(p);
    return t->kind == CSG_TOK_WORD && t->kw == kw;
}

static inline bool lang_is_ident(parser *p)
{
    const csg_token *t = lang_tok(p);
    return t->kind == CSG_TOK_WORD && t->kw == CSG_KW_NONE;
}

/* Whether the token after the last one read, in the current frame, is the
 * punctuation c (a look without reading: nothing runs, no frame ends). */
bool lang_raw_peek_punct(parser *p, int c);
/* The current frame (the innermost). */
frame *lang_frame(parser *p);
/* Reads one raw token from the current frame into *t, leaving the frame
 * at its end (skipping: the caller handles the end).  Counts tokens. */
bool lang_raw_token(parser *p, csg_token *t);
/* Pushes a frame (a macro call) reading `lx`; false past the limits. */
bool lang_push_macro_frame(parser *p, const lang_macro *m, csg_loc call);
/* Leaves the current frame (end of an include or a macro body). */
bool lang_pop_frame(parser *p);

/* ---- source.c: messages, nesting, files ------------------------------------------- */

/* "<what expected ...>, got <token>" — or the unsupported-word message. */
bool lang_expected(parser *p, const char *what);
/* "'}' expected (to close 'union' at 12:3), got 'sphere'" */
bool lang_expected_close(parser *p, int closer, const char *opener, csg_loc at);
/* Consumes "{" after the keyword `name`. */
bool lang_expect_open(parser *p, const char *name);
/* Consumes the punctuation c, or "'c' expected <context>, got ...". */
bool lang_expect_punct(parser *p, int c, const char *context);
/* Consumes the ';' that ends the directive '#directive' at `at`. */
bool lang_expect_semicolon(parser *p, const char *directive, csg_loc at);
/* The message about an unsupported construct at `at` (and notes it for a
 * declaration in progress: declare.c). */
bool lang_unsupported(parser *p, const char *construct, csg_loc at);
/* One more (enter) or one less (leave) level of nesting at `loc`. */
bool lang_enter(parser *p, csg_loc loc);
void lang_leave(parser *p);
/* The text of the current token for messages: at most 40 characters. */
void lang_describe(parser *p, char *buf, size_t size);

/* Reads a whole regular file of at most CSG_PARSE_MAX_FILE bytes into
 * malloc'd memory; NULL with *why set otherwise (errno text or a reason). */
char *lang_read_file(const char *path, size_t *len, char *why, size_t why_size);
/* The same for an open descriptor (not closed), at most `max` bytes. */
char *lang_read_fd(int fd, long max, size_t *len, char *why, size_t why_size);
/* Reads the top file: its name `path` and its `text` are in the arena. */
bool lang_parse_main(parser *p, const char *path, const char *text, size_t len);
/* #include STRING; the directive was consumed. */
bool lang_include(parser *p, csg_loc at);
/* " (in macro 'M' called at f:1:2, in 'x.inc' included at ...)" for the
 * open frames, or "" at the top level, into buf. */
void lang_frame_chain(parser *p, char *buf, size_t size);

/* ---- directives.c ---------------------------------------------------------------------- */

/* Runs the directive `t` (already consumed) or the macro call `t`. */
bool lang_run_directive(parser *p, const csg_token *t);
/* Calls the macro m: the current token is the '(' after its name. */
bool lang_call_macro(parser *p, const lang_macro *m, csg_loc at);
/* The end of a frame was reached: every block opened in it must be closed. */
bool lang_check_frame_end(parser *p);

/* ---- declare.c ------------------------------------------------------------------------------ */

bool lang_declare(parser *p, bool local, csg_loc at);
bool lang_undef(parser *p, csg_loc at);
bool lang_default(parser *p, csg_loc at);
/* A right-hand value: what #declare binds or a macro argument. */
bool lang_parse_rvalue(parser *p, datum *out, bool *needs_semicolon);
/* The datum named by the current identifier (with its [subscripts] for an
 * array element), of kind `want` (want_name in messages); consumes it. */
bool lang_lookup(parser *p, enum sym_kind want, const char *want_name, const datum **out);
/* The element of the array `name` (a token of its name) that the
 * subscripts [i][j]... at the current token select: *slot (NULL: not
 * set).  Valid until the next token is read. */
bool lang_element_slot(parser *p, const csg_token *name, datum ***slot);
/* Whether the current identifier names a datum of kind `kind` (an array
 * whose elements are of that kind included). */
bool lang_names(parser *p, enum sym_kind kind);
/* "'T' (declared at f:1:2) needs 'normal' (f:3:4), ..." for a poisoned use. */
bool lang_use_unsupported(parser *p, const lang_unusable *why, csg_loc at);
/* Copies src into *dst (strings and arrays deep). */
bool lang_datum_copy(parser *p, datum *dst, const datum *src);
void lang_datum_free(datum *d);

/* ---- symbols.c ---------------------------------------------------------------------------- */

/* The innermost binding of `name`, or NULL (a parameter passed by
 * reference: the binding it stands for, here and below). */
symbol *lang_sym_find(parser *p, const char *name, size_t len);
/* #declare: the innermost binding of name, else a new global one. */
symbol *lang_sym_declare(parser *p, const char *name, size_t len, csg_loc at);
/* #local (and #for): the binding in the innermost scope, new if needed. */
symbol *lang_sym_local(parser *p, const char *name, size_t len, csg_loc at);
/* A macro parameter: its own binding in the innermost scope, standing for
 * `ref` (the caller's binding; NULL: passed by value). */
symbol *lang_sym_param(parser *p, const char *name, size_t len, csg_loc at, symbol *ref);
/* Removes the innermost binding of name (#undef); false when there is none. */
bool lang_sym_undef(parser *p, const char *name, size_t len);
bool lang_scope_push(parser *p);
void lang_scope_pop(parser *p);
/* Replaces the symbol's value by *d (taken over, not copied). */
void lang_sym_assign(symbol *sym, datum *d);
/* "a float", "a pigment", ... */
const char *lang_kind_name(const datum *d);
/* #include "colors.inc" without the file: the built-in colours (colors.c). */
bool lang_declare_builtin_colors(parser *p);
/* image_width, image_height (global floats from the options). */
bool lang_declare_predefined(parser *p);
void lang_symbols_free(parser *p);

/* ---- strings.c ------------------------------------------------------------------------------- */

/* True when the current token begins a string expression. */
bool lang_is_string_start(parser *p);
/* A string expression into malloc'd *out (NUL-terminated). */
bool lang_parse_string(parser *p, char **out);

/* ---- texture.c -------------------------------------------------------------------------------- */

bool lang_parse_pigment(parser *p, csg_pigment *pig);
bool lang_parse_finish(parser *p, csg_finish *f);
/* v as POV-Ray keeps a single-precision (SNGL, COLC) setting: rounded to
 * a float into *out; false (an error at `at` naming `what`) when no float
 * holds it. */
bool lang_single_float(parser *p, double v, csg_loc at, const char *what, double *out);
bool lang_parse_texture(parser *p, csg_texture *t);
bool lang_parse_interior(parser *p, csg_interior *in);
/* normal { [NORMAL_ID] [PATTERN [,] [AMOUNT]] MODIFIERS }, editing *n (a
 * normal not given yet starts from the default texture's). */
bool lang_parse_normal(parser *p, csg_normal *n);
/* material { [MATERIAL_ID] texture { }... interior { } TRANSFORMS }, starting
 * from *m (an object's texture and interior, or nothing). */
bool lang_parse_material(parser *p, lang_material *m);
/* *out: the layers of `top` over those of `under` (POV-Ray's
 * Link_Textures: the texture written last is on top); `under` NULL: top
 * as it is.  An error (at `at`) to layer over or with a texture_map. */
bool lang_texture_link(parser *p, const csg_texture *under, const csg_texture *top,
                       csg_texture *out, csg_loc at);
/* The texture seen through transform x: every layer's pigment and normal,
 * or a texture_map's pattern (copies of the layers in the arena). */
bool lang_texture_transform(parser *p, csg_texture *t, const csg_xform *x);
/* Whether a transform changes anything of t (a pattern somewhere). */
bool lang_texture_patterned(const csg_texture *t);
bool lang_parse_color_map(parser *p, lang_color_map *out);
/* sky_sphere { [SKY_ID] pigment {}... emission COLOR TRANSFORMS }. */
bool lang_parse_sky_sphere(parser *p, csg_sky *sky);
/* Transforms (translate V, rotate V, scale V|F, matrix <...>): true when the
 * current token is one; lang_parse_transform composes it after *x. */
bool lang_is_transform(parser *p);
bool lang_parse_transform(parser *p, csg_xform *x);
/* The pigment seen through transform x (applied after its own). */
/* pig's pattern moved by x: false (an error at the last transform read)
 * when that overflows or collapses an axis. */
bool lang_pigment_transform(parser *p, csg_pigment *pig, const csg_xform *x);

/* ---- parser.c ----------------------------------------------------------------------------------- */

/* "out of memory"; returns false. */
bool lang_oom(parser *p);
/* Arena memory that lives as long as the scene (NULL: out of memory). */
void *lang_alloc(parser *p, size_t size);
char *lang_strndup(parser *p, const char *text, size_t len);
bool lang_vec_push(parser *p, vec *v, size_t elem, const void *item);
/* Statements up to the end of the main file. */
bool lang_parse_statements(parser *p);
bool lang_is_object_start(parser *p);
/* ... or a declared object's name (an element of an array of them). */
bool lang_is_object(parser *p);
/* Any object; the current token is its keyword. */
bool lang_parse_object(parser *p, csg_object **out);
bool lang_parse_camera(parser *p, csg_camera_src *c);
/* A new object of `kind` written at loc (identity transform, inherited
 * texture and interior); NULL on error. */
csg_object *lang_new_object(parser *p, enum csg_object_kind kind, csg_loc loc);

/* ---- outline.c ---------------------------------------------------------------------------------- */

/* prism { ... }'s parameters (after the brace) into o. */
bool lang_parse_prism(parser *p, csg_object *o);
/* text { ttf ... }'s parameters (after the brace): the glyphs become the
 * children of the union `text`. */
bool lang_parse_text(parser *p, csg_object *text);

/* ---- fileio.c --------------------------------------------------------------------------------- */

/* #fopen NAME STRING read|write|append, #fclose NAME, #read (NAME, ...),
 * #write (NAME, ...); the directive was consumed. */
bool lang_fopen(parser *p, csg_loc at);
bool lang_fclose(parser *p, csg_loc at);
bool lang_read(parser *p, csg_loc at);
bool lang_write(parser *p, csg_loc at);
/* file_exists(STRING): the current token is the keyword. */
bool lang_parse_file_exists(parser *p, double *out);
/* The file the scene wrote under the #include name `given` (relative,
 * no '..'): its normalised *name and its current text; false: none. */
bool lang_written_find(parser *p, const char *given, const char **name, const char **data,
                       size_t *len);
/* The written files into the scene (finish_scene); false: out of memory. */
bool lang_files_to_scene(parser *p);
void lang_files_free(parser *p);

/* ---- strings.c: literals -------------------------------------------------------------------- */

/* A string literal's text, its escapes replaced (malloc'd). */
char *lang_string_literal(parser *p, const csg_token *t);

/* ---- source.c: files --------------------------------------------------------------------------- */

/* Where file `name` is, found as an #include file is (the including
 * file's folder, the scene's, the library folders: *searched); NULL when
 * out of memory. */
char *lang_find_file(parser *p, const char *name, bool *searched);
bool lang_file_exists(const char *path);

/* Object o (and its textures) moved by transform x after its own. */
bool lang_object_transform(parser *p, csg_object *o, const csg_xform *x);

#endif
