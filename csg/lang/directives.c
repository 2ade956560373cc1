/*
 * directives.c — the directives the token layer runs wherever they appear
 * (POV-Ray 3.7's model: a loop re-reads its tokens, a macro call reads its
 * body, a false branch is skipped token by token):
 *
 *   #if (F) ... [#elseif (F) ...] [#else ...] #end    #ifdef (NAME)  #ifndef (NAME)
 *   #while (F) ... #end       #for (NAME, START, END [, STEP]) ... #end
 *   #switch (F) #case (F) ... [#break] #range (LO, HI) ... #else ... #end
 *   #macro NAME(P1, ...) ... #end        NAME(ARG1, ...)   (a call)
 *   #declare #local #undef #default #include #version
 *   #debug STRING  #warning STRING  #error STRING
 *   #fopen #fclose #read #write (fileio.c)
 *
 * Blocks being run are kept on p->conds (a COND_IF branch, a loop body, the
 * cases of a switch after the first match); a part not run is skipped by
 * skip_block, which lexes raw tokens of the current frame and counts the
 * blocks inside (#if #ifdef #ifndef #while #for #switch #macro ... #end),
 * so it stops at the #else, #elseif, #case, #range or #end of the block
 * itself.  A loop's #end goes back to the lexer position saved when the
 * loop started and re-reads from there; when the loop is done, reading goes
 * on after that #end (its position was saved as the loop ended).  A #break
 * skips to the #end of the innermost loop or switch of its frame, or
 * leaves the macro it is in.  A macro call parses its arguments (rvalues,
 * declare.c) in the caller's scope, opens a scope binding the parameters
 * and pushes a frame over the body (source.c); the frame ends at the
 * body's #end.
 *
 * Limits (errors, never a hang or a crash): CSG_PARSE_MAX_CONDS blocks open
 * at once, CSG_PARSE_MAX_MACRO_DEPTH macro calls (source.c), and the token
 * budget of the parse (source.c), which every re-read token counts against.
 * A block must end in the frame (file or macro body) it started in.
 */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "parse_internal.h"

#define LANG_EPSILON 1e-10

/* ---- the block stack ------------------------------------------------------------ */

static cond *cond_top(parser *p)
{
    return (cond *)p->conds.data + p->conds.count - 1;
}

/* The innermost block opened in the current frame, or NULL. */
static cond *frame_top(parser *p)
{
    return p->conds.count > lang_frame(p)->cond_base ? cond_top(p) : NULL;
}

static bool push_cond(parser *p, enum cond_kind kind, csg_loc at)
{
    if (p->conds.count >= CSG_PARSE_MAX_CONDS) {
        csg_error(p->d, at, "more than %d '#if', '#while', '#for' or '#switch' open at once",
                  CSG_PARSE_MAX_CONDS);
        return false;
    }
    cond c;
    memset(&c, 0, sizeof c);
    c.kind = kind;
    c.at = at;
    c.frame = p->frames.count - 1;
    return lang_vec_push(p, &p->conds, sizeof c, &c);
}

static const char *cond_name(const cond *c)
{
    switch (c->kind) {
    case COND_IF: return "#if";
    case COND_WHILE: return "#while";
    case COND_FOR: return "#for";
    default: return "#switch";
    }
}

bool lang_check_frame_end(parser *p)
{
    cond *c = frame_top(p);
    if (!c)
        return true;
    const frame *f = lang_frame(p);
    csg_loc at = {f->lx.file, f->lx.line, f->lx.col};
    if (f->kind == FRAME_MACRO)
        csg_error(p->d, at, "'#end' expected (to close '%s' at %d:%d) before the end of macro '%s'",
                  cond_name(c), c->at.line, c->at.col, f->macro);
    else
        csg_error(p->d, at, "'#end' expected (to close '%s' at %d:%d), got end of file",
                  cond_name(c), c->at.line, c->at.col);
    return false;
}

/* ---- skipping ---------------------------------------------------------------------- */

/* The directives that open a block closed by #end. */
static bool opens_block(enum csg_kw kw)
{
    return kw == CSG_KW_IF || kw == CSG_KW_IFDEF || kw == CSG_KW_IFNDEF || kw == CSG_KW_WHILE ||
           kw == CSG_KW_FOR || kw == CSG_KW_SWITCH || kw == CSG_KW_MACRO;
}

enum { STOP_ELSE = 1, STOP_ELSEIF = 2, STOP_CASE = 4 };

/* Skips raw tokens of the current frame up to the directive that ends the
 * part being skipped: #end at depth 0 always (depth: blocks already open
 * inside the part), #else / #elseif / #case and #range when `stops` says
 * so.  *stop receives that directive (consumed).  `what` and `at` name the
 * block for the message at the end of the frame. */
static bool skip_block(parser *p, int depth, unsigned stops, const char *what, csg_loc at,
                       csg_token *stop)
{
    for (;;) {
        if (!lang_raw_token(p, stop))
            return false;
        if (stop->kind == CSG_TOK_EOF) {
            csg_error(p->d, stop->loc, "'#end' expected (to close '%s' at %d:%d), got %s", what,
                      at.line, at.col, lang_frame(p)->kind == FRAME_MACRO
                                           ? "the end of the macro" : "end of file");
            return false;
        }
        if (stop->kind != CSG_TOK_DIRECTIVE)
            continue;
        enum csg_kw kw = stop->kw;
        if (opens_block(kw)) {
            depth++;
        } else if (kw == CSG_KW_END) {
            if (depth-- == 0)
                return true;
        } else if (depth == 0 && (((stops & STOP_ELSE) && kw == CSG_KW_ELSE) ||
                                  ((stops & STOP_ELSEIF) && kw == CSG_KW_ELSEIF) ||
                                  ((stops & STOP_CASE) && (kw == CSG_KW_CASE || kw == CSG_KW_RANGE)))) {
            return true;
        }
    }
}

/* ---- #if, #ifdef, #ifndef, #else, #elseif --------------------------------------- */

/* (NAME) for #ifdef: true when NAME (or the array element NAME[i]...) is
 * declared. */
static bool parse_defined(parser *p, bool *out)
{
    if (!lang_expect_punct(p, '(', "after '#ifdef'"))
        return false;
    const csg_token *t = lang_tok_raw(p);
    if (t->kind != CSG_TOK_WORD)
        return lang_expected(p, "an identifier expected");
    csg_token name = *t;
    symbol *sym = t->kw == CSG_KW_NONE ? lang_sym_find(p, t->text, t->len) : NULL;
    *out = sym != NULL || t->kw != CSG_KW_NONE; /* a keyword: POV-Ray calls it defined */
    if (!lang_next(p))
        return false;
    if (sym && sym->d.kind == SYM_ARRAY && lang_is_punct(p, '[')) {
        datum **slot;
        if (!lang_element_slot(p, &name, &slot))
            return false;
        *out = *slot != NULL;
    }
    return lang_expect_punct(p, ')', "after the name in '#ifdef'");
}

/* The branch to run after a false condition: the next #elseif whose
 * condition holds, the #else, or none (the #end). */
static bool skip_to_branch(parser *p, csg_loc at)
{
    for (;;) {
        csg_token stop;
        if (!skip_block(p, 0, STOP_ELSE | STOP_ELSEIF, "#if", at, &stop))
            return false;
        if (stop.kw == CSG_KW_END)
            return true;
        if (stop.kw == CSG_KW_ELSE) {
            if (!push_cond(p, COND_IF, at))
                return false;
            cond_top(p)->in_else = true;
            return true;
        }
        double f;
        if (!lang_parse_float_param(p, &f))
            return false;
        if (lang_truth(f))
            return push_cond(p, COND_IF, at);
    }
}

static bool directive_if(parser *p, const csg_token *d)
{
    bool yes = false;
    if (d->kw == CSG_KW_IF) {
        double f;
        if (!lang_parse_float_param(p, &f))
            return false;
        yes = lang_truth(f);
    } else {
        if (!parse_defined(p, &yes))
            return false;
        yes = d->kw == CSG_KW_IFDEF ? yes : !yes;
    }
    return yes ? push_cond(p, COND_IF, d->loc) : skip_to_branch(p, d->loc);
}

/* #else or #elseif met while running: the branch before it was taken. */
static bool directive_else(parser *p, const csg_token *d)
{
    cond *c = frame_top(p);
    const char *name = d->kw == CSG_KW_ELSE ? "#else" : "#elseif";
    if (c && c->kind == COND_SWITCH && d->kw == CSG_KW_ELSE)
        return true; /* a case falls through into #else, as in POV-Ray */
    if (!c || c->kind != COND_IF || c->in_else) {
        csg_error(p->d, d->loc, "'%s' without a matching '#if'", name);
        return false;
    }
    csg_loc at = c->at;
    csg_token stop;
    p->conds.count--;
    return skip_block(p, 0, 0, "#if", at, &stop);
}

/* ---- loops ---------------------------------------------------------------------------- */

static bool directive_while(parser *p, const csg_token *d)
{
    csg_lexer restart = lang_frame(p)->lx;
    double f;
    if (!lang_parse_float_param(p, &f))
        return false;
    if (!lang_truth(f)) {
        csg_token stop;
        return skip_block(p, 0, 0, "#while", d->loc, &stop);
    }
    if (!push_cond(p, COND_WHILE, d->loc))
        return false;
    cond_top(p)->restart = restart;
    return true;
}

/* The #for variable, which must still be a float. */
static symbol *for_variable(parser *p, const cond *c)
{
    symbol *sym = lang_sym_find(p, c->var, strlen(c->var));
    if (!sym || sym->d.kind != SYM_VALUE || sym->d.u.val.dim != 1) {
        csg_error(p->d, c->at, "the #for variable '%s' must stay a float", c->var);
        return NULL;
    }
    return sym;
}

static bool for_continues(double cur, double end, double step)
{
    return step > 0 ? cur < end + LANG_EPSILON : cur > end - LANG_EPSILON;
}

/* #for (NAME, START, END [, STEP]) */
static bool directive_for(parser *p, const csg_token *d)
{
    csg_loc open = lang_tok(p)->loc;
    if (!lang_expect_punct(p, '(', "after '#for'"))
        return false;
    const csg_token *t = lang_tok_raw(p);
    if (t->kind != CSG_TOK_WORD || t->kw != CSG_KW_NONE)
        return lang_expected(p, "a variable name expected in '#for'");
    csg_token name = *t;
    double start, end, step = 1;
    if (!lang_next(p) || (lang_is_punct(p, ',') && !lang_next(p)) ||
        !lang_parse_float(p, &start, NULL) || (lang_is_punct(p, ',') && !lang_next(p)) ||
        !lang_parse_float(p, &end, NULL))
        return false;
    if (lang_is_punct(p, ',') && (!lang_next(p) || !lang_parse_float(p, &step, NULL)))
        return false;
    if (!lang_is_punct(p, ')'))
        return lang_expected_close(p, ')', "(", open);
    if (fabs(step) < LANG_EPSILON) {
        csg_error(p->d, d->loc, "#for: the step must not be 0");
        return false;
    }
    symbol *sym = lang_sym_local(p, name.text, name.len, name.loc);
    if (!sym)
        return false;
    datum v;
    memset(&v, 0, sizeof v);
    v.u.val.dim = 1;
    v.u.val.v[0] = start;
    lang_sym_assign(sym, &v);
    if (!lang_next(p))
        return false;
    if (!for_continues(start, end, step)) {
        csg_token stop;
        return skip_block(p, 0, 0, "#for", d->loc, &stop);
    }
    if (!push_cond(p, COND_FOR, d->loc))
        return false;
    cond *c = cond_top(p);
    c->restart = lang_frame(p)->lx;
    c->var = lang_strndup(p, name.text, name.len);
    c->end = end;
    c->step = step;
    return c->var != NULL;
}

/* #end of a loop: go round again, or on after the #end. */
static bool loop_end(parser *p, cond *c)
{
    frame *f = lang_frame(p);
    csg_lexer after = f->lx;
    bool again;
    if (c->kind == COND_FOR) {
        symbol *sym = for_variable(p, c);
        if (!sym)
            return false;
        sym->d.u.val.v[0] += c->step;
        again = for_continues(sym->d.u.val.v[0], c->end, c->step);
        if (again)
            f->lx = c->restart;
    } else {
        csg_loc at = c->at;
        f->lx = c->restart;
        double v;
        if (!lang_parse_float_param(p, &v))
            return false;
        again = lang_truth(v);
        if (!again) {
            lang_frame(p)->lx = after;
            c = frame_top(p);
            if (!c || c->kind != COND_WHILE) { /* the condition closed blocks: nonsense */
                csg_error(p->d, at, "the '#while' condition changed the blocks open");
                return false;
            }
        }
    }
    if (!again)
        p->conds.count--;
    return true;
}

/* ---- #switch, #case, #range, #break ----------------------------------------------- */

/* The value a #case (F) or #range (LO, HI) matches; the directive consumed. */
static bool case_matches(parser *p, const csg_token *d, double subject, bool *match)
{
    if (d->kw == CSG_KW_CASE) {
        double f;
        if (!lang_parse_float_param(p, &f))
            return false;
        *match = fabs(f - subject) < LANG_EPSILON;
        return true;
    }
    csg_loc open = lang_tok(p)->loc;
    double lo, hi;
    if (!lang_expect_punct(p, '(', "after '#range'") || !lang_parse_float(p, &lo, NULL) ||
        (lang_is_punct(p, ',') && !lang_next(p)) || !lang_parse_float(p, &hi, NULL))
        return false;
    if (!lang_is_punct(p, ')'))
        return lang_expected_close(p, ')', "(", open);
    *match = subject >= lo && subject <= hi;
    return lang_next(p);
}

/* From the #switch value on: the first #case or #range that matches, or
 * #else, is run; none: on after the #end. */
static bool directive_switch(parser *p, const csg_token *d)
{
    double subject;
    if (!lang_parse_float_param(p, &subject))
        return false;
    csg_token t;
    if (!lang_raw_token(p, &t))
        return false;
    if (t.kind != CSG_TOK_DIRECTIVE || (t.kw != CSG_KW_CASE && t.kw != CSG_KW_RANGE)) {
        csg_error(p->d, t.loc, "'#case' or '#range' expected after '#switch'");
        return false;
    }
    for (;;) {
        bool match = t.kw == CSG_KW_ELSE;
        if (t.kw == CSG_KW_END)
            return true;
        if (!match && !case_matches(p, &t, subject, &match))
            return false;
        if (match)
            return push_cond(p, COND_SWITCH, d->loc);
        if (!skip_block(p, 0, STOP_ELSE | STOP_CASE, "#switch", d->loc, &t))
            return false;
    }
}

/* #case or #range met while running: a case falls through. */
static bool directive_case(parser *p, const csg_token *d)
{
    cond *c = frame_top(p);
    if (!c || c->kind != COND_SWITCH) {
        csg_error(p->d, d->loc, "'#%s' outside a '#switch'", d->kw == CSG_KW_CASE ? "case" : "range");
        return false;
    }
    bool ignored;
    return case_matches(p, d, 0, &ignored);
}

static bool directive_break(parser *p, const csg_token *d)
{
    int base = lang_frame(p)->cond_base, k = p->conds.count - 1;
    const cond *cs = p->conds.data;
    while (k >= base && cs[k].kind == COND_IF)
        k--;
    if (k < base) {
        if (lang_frame(p)->kind != FRAME_MACRO) {
            csg_error(p->d, d->loc, "'#break' outside a loop, a '#switch' or a macro");
            return false;
        }
        p->conds.count = base; /* leaves the macro: its blocks end with it */
        return lang_pop_frame(p);
    }
    csg_token stop;
    csg_loc at = cs[k].at;
    const char *what = cond_name(&cs[k]);
    int depth = p->conds.count - 1 - k;
    p->conds.count = k;
    return skip_block(p, depth, 0, what, at, &stop);
}

/* #end met while running. */
static bool directive_end(parser *p, const csg_token *d)
{
    cond *c = frame_top(p);
    if (!c) {
        csg_error(p->d, d->loc,
                  "'#end' without a matching '#if', '#while', '#for', '#switch' or '#macro'");
        return false;
    }
    if (c->kind == COND_WHILE || c->kind == COND_FOR)
        return loop_end(p, c);
    p->conds.count--;
    return true;
}

/* ---- macros ----------------------------------------------------------------------------- */

/* #macro NAME(P1, P2, ...) body #end: the body is skipped and kept. */
static bool directive_macro(parser *p, const csg_token *d)
{
    const csg_token *t = lang_tok_raw(p);
    if (t->kind != CSG_TOK_WORD || t->kw != CSG_KW_NONE)
        return lang_expected(p, "a macro name expected after '#macro'");
    lang_macro *m = lang_alloc(p, sizeof *m);
    if (!m || !(m->name = lang_strndup(p, t->text, t->len)))
        return false;
    m->at = d->loc;
    csg_token name = *t;
    if (!lang_next(p) || !lang_expect_punct(p, '(', "after the macro name"))
        return false;
    while (!lang_is_punct(p, ')')) {
        t = lang_tok_raw(p);
        if (t->kind != CSG_TOK_WORD || t->kw != CSG_KW_NONE)
            return lang_expected(p, "a parameter name expected");
        if (m->param_count == LANG_MAX_PARAMS) {
            csg_error(p->d, t->loc, "a macro has at most %d parameters", LANG_MAX_PARAMS);
            return false;
        }
        if (!(m->params[m->param_count++] = lang_strndup(p, t->text, t->len)) || !lang_next(p) ||
            (lang_is_punct(p, ',') && !lang_next(p)))
            return false;
    }
    csg_token stop;
    m->body = lang_frame(p)->lx; /* the ')' is the last token read */
    if (!lang_next(p))
        return false;
    if (!skip_block(p, 0, 0, "#macro", d->loc, &stop))
        return false;
    m->body.len = stop.pos; /* the body ends at its #end */
    symbol *sym = lang_sym_declare(p, name.text, name.len, name.loc);
    if (!sym)
        return false;
    datum md;
    memset(&md, 0, sizeof md);
    md.kind = SYM_MACRO;
    md.u.macro = m;
    lang_sym_assign(sym, &md);
    return true;
}

/* The binding the current token names when it may be passed by reference
 * (POV-Ray's Parse_RValue: any declared identifier but a macro or a
 * function; csgtrace has no function identifiers), else NULL. */
static symbol *referable_name(parser *p)
{
    const csg_token *t = lang_tok(p);
    if (t->kind != CSG_TOK_WORD || t->kw != CSG_KW_NONE)
        return NULL;
    symbol *sym = lang_sym_find(p, t->text, t->len);
    return sym && sym->d.kind != SYM_MACRO && sym->d.kind != SYM_UNSUPPORTED ? sym : NULL;
}

/* The arguments of a call: rvalues separated by commas, in the caller's
 * scope.  An argument that is one identifier alone is also passed by
 * reference (refs[i]: its binding): POV-Ray then lets the macro's
 * #declare of the parameter change the caller's variable. */
static bool parse_arguments(parser *p, const lang_macro *m, datum *args, symbol **refs,
                            csg_loc open)
{
    for (int i = 0; i < m->param_count; i++) {
        bool semi;
        if (lang_is_punct(p, ')')) {
            csg_error(p->d, lang_tok(p)->loc, "macro '%s' expects %d arguments, got %d", m->name,
                      m->param_count, i);
            return false;
        }
        symbol *named = referable_name(p);
        long first_token = p->tokens; /* the name's, read */
        if (!lang_parse_rvalue(p, &args[i], &semi) || !lang_tok(p))
            return false;
        refs[i] = named && p->tokens == first_token + 1 ? named : NULL; /* read: name, ',' */
        if (lang_is_punct(p, ',') && !lang_next(p))
            return false;
    }
    if (!lang_is_punct(p, ')'))
        return lang_expected_close(p, ')', "(", open);
    return true;
}

bool lang_call_macro(parser *p, const lang_macro *m, csg_loc at)
{
    csg_loc open = lang_tok(p)->loc;
    if (!lang_is_punct(p, '(')) {
        char what[128];
        snprintf(what, sizeof what, "'(' expected after macro '%.60s'", m->name);
        return lang_expected(p, what);
    }
    datum *args = calloc((size_t)m->param_count + 1, sizeof *args); /* kind 0: nothing owned */
    symbol **refs = calloc((size_t)m->param_count + 1, sizeof *refs);
    bool ok = args && refs ? lang_enter(p, open) && lang_next(p) &&
                                 parse_arguments(p, m, args, refs, open) && lang_next(p) &&
                                 lang_scope_push(p)
                           : lang_oom(p);
    for (int i = 0; ok && i < m->param_count; i++) {
        symbol *sym = lang_sym_param(p, m->params[i], strlen(m->params[i]), at, refs[i]);
        ok = sym != NULL;
        if (ok) {
            lang_sym_assign(sym, &args[i]);
            memset(&args[i], 0, sizeof args[i]); /* taken over */
        }
    }
    for (int i = 0; args && i < m->param_count; i++)
        lang_datum_free(&args[i]);
    free(args);
    free(refs);
    if (!ok)
        return false;
    lang_leave(p);
    return lang_push_macro_frame(p, m, at);
}

/* ---- messages -------------------------------------------------------------------------- */

/* #debug, #warning and #error STRING. */
static bool directive_message(parser *p, const csg_token *d)
{
    char *text = NULL;
    if (!lang_parse_string(p, &text))
        return false;
    if (d->kw == CSG_KW_ERROR)
        csg_error(p->d, d->loc, "#error: %s", text);
    else if (p->opt.messages && d->kw == CSG_KW_DEBUG)
        fputs(text, p->opt.messages);
    else if (p->opt.messages)
        fprintf(p->opt.messages, "%s:%d:%d: warning: %s\n", d->loc.file, d->loc.line, d->loc.col,
                text);
    free(text);
    return d->kw != CSG_KW_ERROR;
}

/* #version F; */
static bool directive_version(parser *p, const csg_token *d)
{
    double v;
    if (!lang_parse_float(p, &v, NULL))
        return false;
    p->version = v;
    p->s->version_implied = false;
    return lang_expect_semicolon(p, "version", d->loc);
}

/* ---- dispatch ----------------------------------------------------------------------------- */

static bool run_block_directive(parser *p, const csg_token *d)
{
    switch (d->kw) {
    case CSG_KW_IF: case CSG_KW_IFDEF: case CSG_KW_IFNDEF: return directive_if(p, d);
    case CSG_KW_ELSE: case CSG_KW_ELSEIF: return directive_else(p, d);
    case CSG_KW_WHILE: return directive_while(p, d);
    case CSG_KW_FOR: return directive_for(p, d);
    case CSG_KW_SWITCH: return directive_switch(p, d);
    case CSG_KW_CASE: case CSG_KW_RANGE: return directive_case(p, d);
    case CSG_KW_BREAK: return directive_break(p, d);
    case CSG_KW_END: return directive_end(p, d);
    default: return directive_macro(p, d); /* CSG_KW_MACRO */
    }
}

bool lang_run_directive(parser *p, const csg_token *d)
{
    if (d->kind == CSG_TOK_WORD) {
        symbol *sym = lang_sym_find(p, d->text, d->len);
        return lang_call_macro(p, sym->d.u.macro, d->loc);
    }
    switch (d->kw) {
    case CSG_KW_DECLARE: case CSG_KW_LOCAL: return lang_declare(p, d->kw == CSG_KW_LOCAL, d->loc);
    case CSG_KW_UNDEF: return lang_undef(p, d->loc);
    case CSG_KW_DEFAULT: return lang_default(p, d->loc);
    case CSG_KW_INCLUDE: return lang_include(p, d->loc);
    case CSG_KW_VERSION: return directive_version(p, d);
    case CSG_KW_DEBUG: case CSG_KW_WARNING: case CSG_KW_ERROR: return directive_message(p, d);
    case CSG_KW_FOPEN: return lang_fopen(p, d->loc);
    case CSG_KW_FCLOSE: return lang_fclose(p, d->loc);
    case CSG_KW_READ: return lang_read(p, d->loc);
    case CSG_KW_WRITE: return lang_write(p, d->loc);
    case CSG_KW_IF: case CSG_KW_IFDEF: case CSG_KW_IFNDEF: case CSG_KW_ELSE: case CSG_KW_ELSEIF:
    case CSG_KW_WHILE: case CSG_KW_FOR: case CSG_KW_SWITCH: case CSG_KW_CASE: case CSG_KW_RANGE:
    case CSG_KW_BREAK: case CSG_KW_END: case CSG_KW_MACRO:
        return run_block_directive(p, d);
    case CSG_KW_UNSUPPORTED: {
        char what[64];
        csg_token_describe(d, what, sizeof what);
        return lang_unsupported(p, what, d->loc);
    }
    default: {
        char what[64];
        csg_token_describe(d, what, sizeof what);
        csg_error(p->d, d->loc, "unknown directive %s", what);
        return false;
    }
    }
}
