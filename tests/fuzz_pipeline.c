/*
 * fuzz_pipeline.c — the libFuzzer target of the whole scene pipeline
 * (`make fuzz`; not part of `make test`, whose quick seeded fuzzer is
 * tests/test_fuzz_parser.c).  Each input is a scene text, taken through
 * every stage a render uses, on an 8 x 6 image:
 *
 *   parse -> (error: one "file:line:col: error: " message, nothing else)
 *         -> export -> parse again (an exported scene always reads back)
 *         -> flatten in float and in double -> blob validation
 *         -> every tile through tile_run (trace + shade) -> finite pixels
 *         -> the same blob laid out for paging, every leaf a page and a
 *            budget of the resident part alone (workers/pager.h): every
 *            tile's pixels the in-memory ones, bit for bit (a place the
 *            engine reads a page without naming it shows here)
 *
 * The trace depth is capped at 3: depth is a knob of the render, not of
 * the input's validity, and an uncapped mirror-in-glass scene would make
 * every input slow.  Anything unexpected aborts (libFuzzer reports it with
 * the input); ASan and UBSan watch the rest.
 */
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "../csg/export_pov.h"
#include "../csg/flatten.h"
#include "../csg/lang/parser.h"
#include "../workers/pager.h"
#include "../workers/tile.h"

enum { FUZZ_W = 8, FUZZ_H = 6, FUZZ_TILE = 4, FUZZ_DEPTH = 3 };

static void fuzz_require(int cond, const char *what)
{
    if (!cond) {
        fprintf(stderr, "fuzz_pipeline: %s\n", what);
        abort();
    }
}

/* A failed parse leaves exactly one message of the contract's form. */
static void check_error(const csg_diag *d)
{
    fuzz_require(d->failed, "a failed parse without a message");
    fuzz_require(strstr(d->message, ": error: ") != NULL, "a message without ': error: '");
    fuzz_require(strchr(d->message, '\n') == NULL, "a message of more than one line");
}

typedef struct {
    const void *blob;
    const pager_plan *plan;
} fuzz_pages;

static bool fuzz_fetch(void *arg, const int32_t *pages, int n, unsigned char *out, size_t bytes)
{
    const fuzz_pages *fp = arg;
    size_t at = 0;
    for (int i = 0; i < n; i++) {
        pager_pack_page(fp->blob, &fp->plan->pages[pages[i]], out + at);
        at += fp->plan->pages[pages[i]].bytes;
    }
    return at == bytes;
}

/* pager_fetch_into (--page-fetch get's path): the ranges copied into place. */
static bool fuzz_get(void *arg, const pager_range *ranges, int n, unsigned char *base)
{
    const fuzz_pages *fp = arg;
    for (int k = 0; k < n; k++)
        memcpy(base + ranges[k].off, (const unsigned char *)fp->blob + ranges[k].off, ranges[k].len);
    return true;
}

/* The tiles of blob b rendered through a pager of pages of one leaf each
 * and a budget of the resident part alone (prefetch, the shadow rays'
 * too, on, the pages through a buffer; or off, read in place), equal to
 * `pixels` (the in-memory render's, tile after tile). */
static void render_paged(const csg_blob *b, const float *pixels, bool prefetch)
{
    csg_blob copy = {malloc(b->size ? b->size : 1), b->size};
    fuzz_require(copy.bytes != NULL, "out of memory");
    memcpy(copy.bytes, b->bytes, b->size);
    const char *why = NULL;
    pager_plan plan;
    fuzz_require(pager_relayout(copy.bytes, 1, &why), "the BVH could not be laid out for paging");
    fuzz_require(csg_blob_valid(copy.bytes, copy.size), "the BVH laid out for paging is invalid");
    fuzz_require(pager_plan_make(copy.bytes, 1, &plan, &why), "no page plan");
    size_t len = 0;
    void *packed = pager_pack_resident(copy.bytes, &plan, &len);
    fuzz_pages fp = {copy.bytes, &plan};
    csg_pager p;
    fuzz_require(packed && pager_open(&p, packed, len, plan.resident_bytes, PAGER_LRU, fuzz_fetch,
                                      &fp, &why),
                 "the pager did not open");
    p.prefetch = prefetch;
    p.prefetch_shadows = prefetch; /* (the shadow rays' walks too: workers/shade.c) */
    p.fetch_into = prefetch ? NULL : fuzz_get;
    tile_runner tr;
    fuzz_require(tile_runner_init(&tr, p.base, FUZZ_TILE), "out of memory");
    float rgb[FUZZ_TILE * FUZZ_TILE * 3];
    size_t at = 0;
    for (int i = 0; i < tile_count(&tr.grid); i++) {
        tile_result res;
        tile_run(&tr, i, NULL, rgb, &res);
        tile_rect r = tile_rect_of(&tr.grid, i);
        size_t n = (size_t)r.width * (size_t)r.height * 3;
        fuzz_require(memcmp(rgb, pixels + at, n * sizeof *rgb) == 0,
                     "a paged tile differs from the in-memory one");
        at += n;
    }
    tile_runner_free(&tr);
    pager_close(&p);
    free(packed);
    pager_plan_free(&plan);
    csg_blob_free(&copy);
}

static void render_all(const engine *e, const csg_scene *s)
{
    csg_flatten_opts o = {FUZZ_W, FUZZ_H, FUZZ_DEPTH, -1, 1, 0};
    csg_diag d = {0};
    csg_blob b;
    if (!e->flatten(s, &o, &b, &d)) {
        check_error(&d); /* a scene may be valid syntax and still unflattenable */
        return;
    }
    fuzz_require(csg_blob_valid(b.bytes, b.size), "the flattener wrote an invalid blob");
    tile_runner tr;
    fuzz_require(tile_runner_init(&tr, b.bytes, FUZZ_TILE), "out of memory");
    float pixels[FUZZ_W * FUZZ_H * 3]; /* the tiles' pixels, one after the other */
    size_t at = 0;
    for (int i = 0; i < tile_count(&tr.grid); i++) {
        tile_result res;
        tile_run(&tr, i, NULL, pixels + at, &res);
        tile_rect r = tile_rect_of(&tr.grid, i);
        for (int k = 0; k < r.width * r.height * 3; k++)
            fuzz_require(pixels[at + k] == pixels[at + k] && pixels[at + k] - pixels[at + k] == 0,
                         "a pixel is not finite");
        at += (size_t)r.width * (size_t)r.height * 3;
    }
    tile_runner_free(&tr);
    render_paged(&b, pixels, e == &engine_float);
    csg_blob_free(&b);
}

/* The exported scene parses again. */
static void check_export(const csg_scene *s)
{
    char *text = NULL;
    size_t len = 0;
    FILE *f = open_memstream(&text, &len);
    fuzz_require(f != NULL, "open_memstream");
    csg_diag d = {0};
    bool ok = csg_export_pov(s, f, false, &d);
    fclose(f);
    if (ok) {
        csg_scene back;
        csg_diag d2 = {0};
        csg_scene_init(&back);
        if (!csg_parse_string("exported.pov", text, len, &back, &d2)) {
            fprintf(stderr, "exported scene:\n%s\nerror: %s\n", text, d2.message);
            fuzz_require(0, "an exported scene does not parse");
        }
        csg_scene_free(&back);
    } else {
        check_error(&d);
    }
    free(text);
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    /* the built-in colors.inc only, and a token budget so that loops that
     * never end stop fast */
    csg_parse_options o;
    csg_parse_options_default(&o);
    o.no_default_library = true;
    o.max_tokens = 20000;
    csg_scene s;
    csg_diag d = {0};
    csg_scene_init(&s);
    if (!csg_parse_string_opts("fuzz.pov", (const char *)data, size, &o, &s, &d)) {
        check_error(&d);
        csg_scene_free(&s);
        return 0;
    }
    check_export(&s);
    render_all(&engine_float, &s);
    render_all(&engine_double, &s);
    csg_scene_free(&s);
    return 0;
}
