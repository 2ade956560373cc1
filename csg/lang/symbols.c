/*
 * symbols.c — the symbol table of the scene language: the names that
 * #declare (and #local: csgtrace has one global scope) bind to a value,
 * pigment, finish, texture, interior or object.
 *
 * Algorithm: open addressing with linear probing on a 64-bit FNV-1a hash
 * of the name; the table of pointers is malloc'd (256 slots to start) and
 * doubled before it would become more than half full.  Symbols and their
 * names live in the scene's arena.  Declaring a name again replaces the
 * symbol's contents in place, whatever the old and new kinds.
 *
 * Invariants: sym_cap is 0 or a power of two with 2 * sym_count <= sym_cap,
 * so every probe ends at an empty slot; a symbol, once created, stays at the
 * same address until the parse ends.
 *
 * Messages on a lookup, Lua-style, at the identifier:
 *   undeclared identifier 'R'
 *   'R' is a float, not a pigment
 */
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "parse_internal.h"

static uint64_t hash_name(const char *s, size_t len)
{
    uint64_t h = 1469598103934665603ull;
    for (size_t i = 0; i < len; i++)
        h = (h ^ (unsigned char)s[i]) * 1099511628211ull;
    return h;
}

static symbol **sym_slot(symbol **table, size_t cap, const char *name, size_t len)
{
    size_t i = (size_t)hash_name(name, len) & (cap - 1);
    while (table[i] && !(table[i]->len == len && memcmp(table[i]->name, name, len) == 0))
        i = (i + 1) & (cap - 1);
    return &table[i];
}

static symbol *sym_find(const parser *p, const char *name, size_t len)
{
    if (!p->sym_cap)
        return NULL;
    return *sym_slot(p->syms, p->sym_cap, name, len);
}

/* The symbol `name`, created (zeroed, kind SYM_VALUE) when new. */
static symbol *sym_define(parser *p, const char *name, size_t len)
{
    if ((p->sym_count + 1) * 2 > p->sym_cap) {
        size_t cap = p->sym_cap ? p->sym_cap * 2 : 256;
        symbol **table = calloc(cap, sizeof *table);
        if (!table) {
            lang_oom(p);
            return NULL;
        }
        for (size_t i = 0; i < p->sym_cap; i++)
            if (p->syms[i])
                *sym_slot(table, cap, p->syms[i]->name, p->syms[i]->len) = p->syms[i];
        free(p->syms);
        p->syms = table;
        p->sym_cap = cap;
    }
    symbol **slot = sym_slot(p->syms, p->sym_cap, name, len);
    if (!*slot) {
        symbol *sym = lang_alloc(p, sizeof *sym);
        char *copy = lang_strndup(p, name, len);
        if (!sym || !copy)
            return NULL;
        sym->name = copy;
        sym->len = len;
        *slot = sym;
        p->sym_count++;
    }
    return *slot;
}

/* Declares `name` as *def: a new symbol, or an old one of any kind
 * replaced in place (its arena copy of the name is kept). */
bool lang_sym_set(parser *p, const char *name, size_t len, const symbol *def)
{
    symbol *sym = sym_define(p, name, len);
    if (!sym)
        return false;
    const char *keep = sym->name;
    size_t keep_len = sym->len;
    *sym = *def;
    sym->name = keep;
    sym->len = keep_len;
    return true;
}

static const char *sym_kind_name(const symbol *sym)
{
    switch (sym->kind) {
    case SYM_VALUE:
        return sym->val.dim == 1 ? "a float" : sym->val.dim == 5 ? "a color" : "a vector";
    case SYM_PIGMENT: return "a pigment";
    case SYM_FINISH: return "a finish";
    case SYM_TEXTURE: return "a texture";
    case SYM_INTERIOR: return "an interior";
    case SYM_OBJECT: return "an object";
    }
    return "?";
}

/* The declared symbol named by the current identifier, of kind `want`:
 * "undeclared identifier 'R'" or "'R' is a float, not a pigment". */
bool lang_lookup(parser *p, enum sym_kind want, const char *want_name, symbol **out)
{
    symbol *sym = sym_find(p, p->tok.text, p->tok.len);
    if (!sym) {
        csg_error(p->d, p->tok.loc, "undeclared identifier '%.*s'", (int)p->tok.len, p->tok.text);
        return false;
    }
    if (sym->kind != want) {
        csg_error(p->d, p->tok.loc, "'%.*s' is %s, not %s", (int)p->tok.len, p->tok.text,
                  sym_kind_name(sym), want_name);
        return false;
    }
    *out = sym;
    return lang_next(p);
}

/* The current identifier's symbol when it is declared with kind `kind`. */
symbol *lang_peek_sym(const parser *p, enum sym_kind kind)
{
    if (!lang_is_ident(p))
        return NULL;
    symbol *sym = sym_find(p, p->tok.text, p->tok.len);
    return sym && sym->kind == kind ? sym : NULL;
}

/* #include "colors.inc": every built-in colour (colors.c), a 5-vector. */
bool lang_declare_builtin_colors(parser *p)
{
    for (int i = 0; i < csg_builtin_color_count(); i++) {
        double c[5];
        const char *name = csg_builtin_color_at(i, c);
        symbol *sym = sym_define(p, name, strlen(name));
        if (!sym)
            return false;
        sym->kind = SYM_VALUE;
        sym->val.dim = 5;
        memcpy(sym->val.v, c, sizeof c);
    }
    return true;
}

void lang_symbols_free(parser *p)
{
    free(p->syms);
    p->syms = NULL;
    p->sym_cap = p->sym_count = 0;
}
