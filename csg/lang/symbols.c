/*
 * symbols.c — the symbol table of the scene language: the names that
 * #declare, #local, #macro, #for and macro parameters bind, in nested
 * scopes, as POV-Ray 3.7 does.
 *
 * Scopes: scope 0 is the global one; every #include file and every macro
 * call opens one (closed at its end).  #declare binds in the innermost
 * scope that already binds the name, else in the global scope; #local (and
 * a parameter, a #for variable) binds in the innermost scope, hiding any
 * outer binding until that scope closes.  Lookups find the innermost
 * binding.
 *
 * Algorithm: an open-addressing hash (linear probing, 64-bit FNV-1a) of
 * every name ever bound; each slot keeps the innermost binding, and each
 * symbol the binding it hides (`shadowed`), so a lookup is one probe and
 * closing a scope restores the hidden bindings.  The table is doubled
 * before it is half full; names are never removed (a name whose bindings
 * are all gone keeps an empty slot).  Symbols are malloc'd and freed with
 * their scope; what they hold is freed with them (lang_datum_free).
 *
 * Invariants: name_cap is 0 or a power of two with 2 * name_used <=
 * name_cap; along a name's chain (top, shadowed, ...) the scopes strictly
 * decrease; scopes.data[k] lists the symbols of scope k, newest first.
 *
 * Messages on a lookup, Lua-style, at the identifier (declare.c):
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

static struct lang_name *name_slot(struct lang_name *table, size_t cap, const char *name,
                                   size_t len)
{
    size_t i = (size_t)hash_name(name, len) & (cap - 1);
    while (table[i].name && !(table[i].len == len && memcmp(table[i].name, name, len) == 0))
        i = (i + 1) & (cap - 1);
    return &table[i];
}

static struct lang_name *name_find(parser *p, const char *name, size_t len)
{
    if (!p->name_cap)
        return NULL;
    struct lang_name *n = name_slot(p->names, p->name_cap, name, len);
    return n->name ? n : NULL;
}

static bool names_grow(parser *p)
{
    size_t cap = p->name_cap ? p->name_cap * 2 : 256;
    struct lang_name *table = calloc(cap, sizeof *table);
    if (!table)
        return lang_oom(p);
    for (size_t i = 0; i < p->name_cap; i++)
        if (p->names[i].name)
            *name_slot(table, cap, p->names[i].name, p->names[i].len) = p->names[i];
    free(p->names);
    p->names = table;
    p->name_cap = cap;
    return true;
}

/* The slot of `name`, created when new. */
static struct lang_name *name_get(parser *p, const char *name, size_t len)
{
    struct lang_name *n = name_find(p, name, len);
    if (n)
        return n;
    if ((p->name_used + 1) * 2 > p->name_cap && !names_grow(p))
        return NULL;
    n = name_slot(p->names, p->name_cap, name, len);
    n->name = malloc(len + 1);
    if (!n->name) {
        lang_oom(p);
        return NULL;
    }
    memcpy(n->name, name, len);
    n->name[len] = '\0';
    n->len = len;
    n->top = NULL;
    p->name_used++;
    return n;
}

/* The binding sym stands for: itself, or the caller's binding a parameter
 * passed by reference names (never a parameter itself: see lang_sym_param). */
static symbol *resolved(symbol *sym)
{
    return sym && sym->ref ? sym->ref : sym;
}

symbol *lang_sym_find(parser *p, const char *name, size_t len)
{
    struct lang_name *n = name_find(p, name, len);
    return n ? resolved(n->top) : NULL;
}

/* A new binding of n in `scope`, hiding n's current one (which is in an
 * outer scope, or none when scope is the global one). */
static symbol *bind(parser *p, struct lang_name *n, int scope, csg_loc at)
{
    symbol *sym = calloc(1, sizeof *sym);
    if (!sym) {
        lang_oom(p);
        return NULL;
    }
    sym->name = n->name;
    sym->len = n->len;
    sym->d.kind = SYM_VALUE;
    sym->d.u.val.dim = 1;
    sym->scope = scope;
    sym->declared_at = at;
    symbol **head = (symbol **)p->scopes.data + scope;
    sym->shadowed = n->top; /* NULL for a new global: see lang_sym_declare */
    n->top = sym;
    sym->next_in_scope = *head;
    *head = sym;
    return sym;
}

symbol *lang_sym_declare(parser *p, const char *name, size_t len, csg_loc at)
{
    struct lang_name *n = name_get(p, name, len);
    if (!n)
        return NULL;
    return n->top ? resolved(n->top) : bind(p, n, 0, at);
}

symbol *lang_sym_local(parser *p, const char *name, size_t len, csg_loc at)
{
    struct lang_name *n = name_get(p, name, len);
    if (!n)
        return NULL;
    int scope = p->scopes.count - 1;
    return n->top && n->top->scope == scope ? resolved(n->top) : bind(p, n, scope, at);
}

symbol *lang_sym_param(parser *p, const char *name, size_t len, csg_loc at, symbol *ref)
{
    struct lang_name *n = name_get(p, name, len);
    if (!n)
        return NULL;
    int scope = p->scopes.count - 1;
    symbol *sym = n->top && n->top->scope == scope ? n->top : bind(p, n, scope, at);
    if (sym)
        sym->ref = resolved(ref);
    return sym;
}

/* sym is going: the parameters of the scopes inside its own that stand for
 * it keep the copy they were given (POV-Ray would read freed memory). */
static void forget_references_to(parser *p, const symbol *sym)
{
    for (int k = sym->scope + 1; k < p->scopes.count; k++)
        for (symbol *s = ((symbol **)p->scopes.data)[k]; s; s = s->next_in_scope)
            if (s->ref == sym)
                s->ref = NULL;
}

static void sym_free(symbol *sym)
{
    lang_datum_free(&sym->d);
    free(sym);
}

bool lang_sym_undef(parser *p, const char *name, size_t len)
{
    struct lang_name *n = name_find(p, name, len);
    if (!n || !n->top)
        return false;
    symbol *sym = n->top;
    symbol **link = (symbol **)p->scopes.data + sym->scope;
    while (*link != sym)
        link = &(*link)->next_in_scope;
    *link = sym->next_in_scope;
    n->top = sym->shadowed;
    forget_references_to(p, sym);
    sym_free(sym);
    return true;
}

bool lang_scope_push(parser *p)
{
    symbol *none = NULL;
    return lang_vec_push(p, &p->scopes, sizeof none, &none);
}

void lang_scope_pop(parser *p)
{
    symbol *sym = ((symbol **)p->scopes.data)[p->scopes.count - 1];
    while (sym) {
        symbol *next = sym->next_in_scope;
        struct lang_name *n = name_find(p, sym->name, sym->len);
        n->top = sym->shadowed;
        sym_free(sym);
        sym = next;
    }
    p->scopes.count--;
}

void lang_sym_assign(symbol *sym, datum *d)
{
    lang_datum_free(&sym->d);
    sym->d = *d;
}

const char *lang_kind_name(const datum *d)
{
    switch (d->kind) {
    case SYM_VALUE:
        return d->u.val.dim == 1 ? "a float" : d->u.val.dim == 5 ? "a color" : "a vector";
    case SYM_STRING: return "a string";
    case SYM_PIGMENT: return "a pigment";
    case SYM_FINISH: return "a finish";
    case SYM_TEXTURE: return "a texture";
    case SYM_INTERIOR: return "an interior";
    case SYM_NORMAL: return "a normal";
    case SYM_MATERIAL: return "a material";
    case SYM_OBJECT: return "an object";
    case SYM_COLOR_MAP: return "a color_map";
    case SYM_CAMERA: return "a camera";
    case SYM_SKY: return "a sky_sphere";
    case SYM_TRANSFORM: return "a transform";
    case SYM_ARRAY: return "an array";
    case SYM_MACRO: return "a macro";
    case SYM_FILE: return "a file";
    case SYM_UNSUPPORTED: return "an unsupported declaration";
    }
    return "?";
}

static bool declare_value(parser *p, const char *name, const value *v)
{
    symbol *sym = lang_sym_declare(p, name, strlen(name), (csg_loc){"<built-in>", 0, 0});
    if (!sym)
        return false;
    datum d;
    memset(&d, 0, sizeof d);
    d.kind = SYM_VALUE;
    d.u.val = *v;
    lang_sym_assign(sym, &d);
    return true;
}

/* #include "colors.inc" found nowhere: every built-in colour (colors.c). */
bool lang_declare_builtin_colors(parser *p)
{
    for (int i = 0; i < csg_builtin_color_count(); i++) {
        value v = {5, {0}};
        const char *name = csg_builtin_color_at(i, v.v);
        if (!declare_value(p, name, &v))
            return false;
    }
    return true;
}

bool lang_declare_predefined(parser *p)
{
    value w = {1, {p->opt.image_width}}, h = {1, {p->opt.image_height}};
    return declare_value(p, "image_width", &w) && declare_value(p, "image_height", &h);
}

void lang_symbols_free(parser *p)
{
    while (p->scopes.count > 0)
        lang_scope_pop(p);
    for (size_t i = 0; i < p->name_cap; i++)
        free(p->names[i].name);
    free(p->names);
    free(p->scopes.data);
    p->names = NULL;
    p->name_cap = p->name_used = 0;
}
