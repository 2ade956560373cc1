/*
 * test_image.c — PNG, PPM and PFM written by csgtrace itself
 * (host/output/stream.c): the process never maps the image module, the
 * files hold the module's pixels (its writer forced with
 * $CSGTRACE_IMAGE_WRITER=oiio) over a sweep of every region of the
 * encoding, a PFM holds every float as it is (the module has no PFM
 * writer: its reader checks it), a streamed file's bytes do not depend on the order its bands
 * are final in nor on its threads, the module's formats stream too, and a
 * failed write names the file and leaves nothing behind.
 */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <dirent.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cmocka.h>

#include "../host/output/image.h"
#include "../host/output/stream.h"
#include "../comm/pixels.h"
#include "same_file.h"

enum { SWEEP_W = 1021, SWEEP_H = 677 };

/* Does /proc/self/maps name `what`? */
static bool mapped(const char *what)
{
    FILE *f = fopen("/proc/self/maps", "r");
    char line[4096];
    bool found = false;
    assert_non_null(f);
    while (!found && fgets(line, sizeof line, f))
        found = strstr(line, what) != NULL;
    fclose(f);
    return found;
}

/* Entries of `dir` besides . and .. */
static int entries(const char *dir)
{
    DIR *d = opendir(dir);
    int n = 0;
    assert_non_null(d);
    for (struct dirent *e; (e = readdir(d));)
        n += strcmp(e->d_name, ".") != 0 && strcmp(e->d_name, "..") != 0;
    closedir(d);
    return n;
}

/* The size of the one file in `dir` (a stream's temporary file). */
static long only_file_size(const char *dir)
{
    DIR *d = opendir(dir);
    char path[512] = "";
    int n = 0;
    assert_non_null(d);
    for (struct dirent *e; (e = readdir(d));)
        if (strcmp(e->d_name, ".") != 0 && strcmp(e->d_name, "..") != 0) {
            snprintf(path, sizeof path, "%s/%s", dir, e->d_name);
            n++;
        }
    closedir(d);
    assert_int_equal(n, 1);
    struct stat st;
    assert_int_equal(stat(path, &st), 0);
    return (long)st.st_size;
}

/* Every float of [0, 1] at a stride of ~500 ulps (both parts of the sRGB
 * curve, every byte's boundary region), then values out of range. */
static float *sweep_image(void)
{
    size_t n = (size_t)SWEEP_W * SWEEP_H * 3;
    float *rgb = malloc(n * sizeof *rgb);
    assert_non_null(rgb);
    uint32_t stride = 0x3f800000u / (uint32_t)(n - 1000) + 1;
    for (size_t i = 0; i < n; i++) {
        uint32_t bits = (uint32_t)i * stride;
        float v;
        memcpy(&v, &bits, sizeof v);
        if (bits > 0x3f800000u)
            v = (float)(i % 7) * 0.5f - 1.0f; /* -1 .. 2: clamped */
        rgb[i] = v;
    }
    return rgb;
}

typedef struct {
    char dir[64];
    char a[96], b[96];
} scratch;

static int scratch_setup(void **state)
{
    scratch *s = calloc(1, sizeof *s);
    if (!s)
        return -1;
    snprintf(s->dir, sizeof s->dir, "/tmp/csgtrace-image-XXXXXX");
    if (!mkdtemp(s->dir)) {
        free(s);
        return -1;
    }
    *state = s;
    return 0;
}

static int scratch_teardown(void **state)
{
    scratch *s = *state;
    unlink(s->a);
    unlink(s->b);
    rmdir(s->dir);
    free(s);
    return 0;
}

static void name_files(scratch *s, const char *ext)
{
    snprintf(s->a, sizeof s->a, "%s/direct.%s", s->dir, ext);
    snprintf(s->b, sizeof s->b, "%s/module.%s", s->dir, ext);
}

/* Must run first: no earlier test may have loaded the module. */
static void test_png_and_ppm_need_no_module(void **state)
{
    scratch *s = *state;
    float rgb[4 * 3 * 3] = {0.0f, 0.5f, 1.0f, 0.25f, 2.0f, -1.0f};
    char err[512] = "";
    const char *exts[] = {"png", "ppm", "pfm"};
    for (int i = 0; i < 3; i++) {
        name_files(s, exts[i]);
        assert_true(img_can_write(s->a, err, sizeof err));
        assert_true(img_write_rgb(s->a, rgb, 4, 3, err, sizeof err));
        unlink(s->a);
    }
    assert_false(mapped("csgtrace-image.so"));
    assert_false(mapped("OpenImageIO"));
}

/* The image settings of a test: the module writes all, at PNG level
 * `level` (-1: csgtrace's). */
static void settings(bool module_writes_all, int level)
{
    img_settings s = {NULL, module_writes_all, level};
    img_configure(&s);
}

/* Files a and b hold the same pixels (read back through the module). */
static void assert_same_pixels(const char *a, const char *b)
{
    float *pa = NULL, *pb = NULL;
    int wa, ha, wb, hb;
    char err[512];
    assert_true(img_read_rgb(a, &pa, &wa, &ha, err, sizeof err));
    assert_true(img_read_rgb(b, &pb, &wb, &hb, err, sizeof err));
    assert_int_equal(wa, wb);
    assert_int_equal(ha, hb);
    assert_memory_equal(pa, pb, (size_t)wa * (size_t)ha * 3 * sizeof *pa);
    free(pa);
    free(pb);
}

/* csgtrace's PNG (csgtrace's settings, and a zlib level with every
 * filter) and PPM hold the pixels of the module's files of the same image,
 * over a sweep of every region of the encoding. */
static void test_own_files_have_the_modules_pixels(void **state)
{
    scratch *s = *state;
    float *rgb = sweep_image();
    char err[512] = "";
    const struct {
        const char *ext;
        int level;
    } cases[] = {{"png", -1}, {"png", 9}, {"ppm", -1}};
    for (size_t c = 0; c < sizeof cases / sizeof cases[0]; c++) {
        name_files(s, cases[c].ext);
        settings(false, cases[c].level);
        assert_int_equal(img_format_of(s->a), cases[c].ext[1] == 'n' ? IMG_FORMAT_PNG
                                                                      : IMG_FORMAT_PPM);
        assert_true(img_write_rgb(s->a, rgb, SWEEP_W, SWEEP_H, err, sizeof err));
        settings(true, cases[c].level);
        assert_int_equal(img_format_of(s->b), IMG_FORMAT_MODULE);
        bool ok = img_write_rgb(s->b, rgb, SWEEP_W, SWEEP_H, err, sizeof err);
        settings(false, -1);
        if (!ok)
            fprintf(stderr, "%s\n", err);
        assert_true(ok);
        assert_same_pixels(s->a, s->b);
        unlink(s->a);
        unlink(s->b);
    }
    free(rgb);
}

/* A little-endian float of the file at p. */
static float float_le(const unsigned char *p)
{
    uint32_t u = (uint32_t)p[0] | (uint32_t)p[1] << 8 | (uint32_t)p[2] << 16 | (uint32_t)p[3] << 24;
    float v;
    memcpy(&v, &u, sizeof v);
    return v;
}

/* A PFM of the sweep (every float of [0, 1] and values out of range, none
 * clamped): PFM's header, the rows bottom up, each float's bits as they
 * are; and the module's reader sees the same image. */
static void test_pfm_holds_every_float(void **state)
{
    scratch *s = *state;
    float *rgb = sweep_image();
    char err[512] = "", head[64];
    name_files(s, "pfm");
    assert_int_equal(img_format_of(s->a), IMG_FORMAT_PFM);
    assert_true(img_write_rgb(s->a, rgb, SWEEP_W, SWEEP_H, err, sizeof err));
    size_t row = (size_t)SWEEP_W * 3 * 4, hlen;
    hlen = (size_t)snprintf(head, sizeof head, "PF\n%d %d\n-1.0\n", SWEEP_W, SWEEP_H);
    FILE *f = fopen(s->a, "rb");
    assert_non_null(f);
    unsigned char *bytes = malloc(hlen + row * SWEEP_H + 1);
    assert_non_null(bytes);
    assert_int_equal(fread(bytes, 1, hlen + row * SWEEP_H + 1, f), hlen + row * SWEEP_H);
    fclose(f);
    assert_memory_equal(bytes, head, hlen);
    for (size_t y = 0; y < SWEEP_H; y++) /* (file row r is image row H - 1 - r) */
        for (size_t i = 0; i < (size_t)SWEEP_W * 3; i++) {
            float want = rgb[y * SWEEP_W * 3 + i];
            float got = float_le(bytes + hlen + (SWEEP_H - 1 - y) * row + i * 4);
            assert_memory_equal(&got, &want, sizeof got);
        }
    float *back = NULL;
    int w, h;
    assert_true(img_read_rgb(s->a, &back, &w, &h, err, sizeof err));
    assert_int_equal(w, SWEEP_W);
    assert_int_equal(h, SWEEP_H);
    assert_memory_equal(back, rgb, (size_t)w * (size_t)h * 3 * sizeof *rgb);
    free(back);
    free(bytes);
    free(rgb);
}

/* A streamed file does not depend on the order its bands are final in, nor
 * on the threads that encode them: tiles final in a scrambled order, one
 * thread, against in order, every CPU; the same bytes; a stream aborted
 * leaves nothing. */
static void test_stream_order_changes_nothing(void **state)
{
    scratch *s = *state;
    float *rgb = sweep_image();
    char err[512] = "";
    const char *exts[] = {"png", "ppm", "pfm"};
    for (int e = 0; e < 3; e++) {
        name_files(s, exts[e]);
        tile_grid g = {SWEEP_W, SWEEP_H, 7, 1, sizeof(float), 0};
        int tiles = tile_count(&g);
        for (int way = 0; way < 2; way++) {
            img_stream *st = img_stream_open(way ? s->b : s->a, rgb, &g, err, sizeof err);
            assert_non_null(st);
            img_stream_start(st);
            for (int k = 0; k < tiles; k++) /* (a permutation when way is 1) */
                img_stream_tile(st, way ? (int)(((long)k * 7919) % tiles) : k);
            img_stream_report r;
            assert_true(img_stream_finish(st, way ? 0 : 1, &r, err, sizeof err));
            assert_int_equal(r.bands, (SWEEP_H + IMG_STREAM_ROWS - 1) / IMG_STREAM_ROWS);
        }
        assert_true(same_file(s->a, s->b));
        unlink(s->a);
        unlink(s->b);
    }
    img_stream *st = img_stream_open(s->a, rgb, &(tile_grid){SWEEP_W, SWEEP_H, 7, 1, 4, 0}, err,
                                     sizeof err);
    assert_non_null(st);
    img_stream_start(st);
    img_stream_tile(st, 0);
    img_stream_abort(st);
    assert_int_equal(entries(s->dir), 0);
    free(rgb);
}

/* The module's formats are streamed too, their rows handed over in order
 * as the bands above them are final: a stream with its tiles final in a
 * scrambled order holds the pixels of the whole image written at once
 * (EXR's floats, TIFF's bytes; their files differ only by the time they
 * were written), every band went through the stream; the rows of the
 * bands that are final are in the file before the stream is finished; an
 * aborted stream leaves nothing. */
static void test_module_formats_stream(void **state)
{
    scratch *s = *state;
    float *rgb = sweep_image();
    char err[512] = "";
    const char *exts[] = {"exr", "tif"};
    tile_grid g = {SWEEP_W, SWEEP_H, 7, 1, sizeof(float), 0};
    int tiles = tile_count(&g), bands = (SWEEP_H + IMG_STREAM_ROWS - 1) / IMG_STREAM_ROWS;
    for (int e = 0; e < 2; e++) {
        name_files(s, exts[e]);
        assert_int_equal(img_format_of(s->b), IMG_FORMAT_MODULE);
        assert_true(img_write_rgb(s->a, rgb, SWEEP_W, SWEEP_H, err, sizeof err));
        img_stream *st = img_stream_open(s->b, rgb, &g, err, sizeof err);
        assert_non_null(st);
        assert_int_equal(entries(s->dir), 2); /* (its temporary file beside the output) */
        img_stream_start(st);
        for (int k = 0; k < tiles; k++)
            img_stream_tile(st, (int)(((long)k * 7919) % tiles));
        img_stream_report r;
        assert_true(img_stream_finish(st, 0, &r, err, sizeof err));
        assert_int_equal(r.bands, bands);
        assert_true(r.bands_early <= bands);
        assert_int_equal(entries(s->dir), 2);
        assert_same_pixels(s->a, s->b);
        unlink(s->a);
        unlink(s->b);
    }
    name_files(s, "exr");
    img_stream *st = img_stream_open(s->a, rgb, &g, err, sizeof err);
    assert_non_null(st);
    long opened = only_file_size(s->dir), now = opened;
    img_stream_start(st);
    for (int k = 0; k < tiles / 2; k++) /* (the first bands final, the rest not) */
        img_stream_tile(st, k);
    for (int wait = 0; wait < 1000 && now == opened; wait++) {
        usleep(10000); /* (the encoder thread hands them over meanwhile: 10 s at most) */
        now = only_file_size(s->dir);
    }
    assert_true(now > opened); /* (their rows compressed into it) */
    img_stream_abort(st);
    assert_int_equal(entries(s->dir), 0);
    free(rgb);
}

/* A folder that does not exist: false, the file named, nothing written;
 * an existing file is left as it was when a write fails. */
static void test_failed_write_names_the_file(void **state)
{
    scratch *s = *state;
    float rgb[2 * 2 * 3] = {0};
    char err[512] = "", path[128];
    const char *exts[] = {"png", "PPM"};
    for (int i = 0; i < 2; i++) {
        snprintf(path, sizeof path, "%s/no-such-folder/out.%s", s->dir, exts[i]);
        assert_false(img_write_rgb(path, rgb, 2, 2, err, sizeof err));
        assert_non_null(strstr(err, path));
        assert_non_null(strstr(err, "No such file or directory"));
    }
    name_files(s, "png");
    FILE *f = fopen(s->a, "w");
    assert_non_null(f);
    fputs("previous\n", f);
    fclose(f);
    assert_false(img_write_rgb(s->a, rgb, 0, 2, err, sizeof err));
    assert_non_null(strstr(err, s->a));
    assert_int_equal(entries(s->dir), 1);
    f = fopen(s->a, "r");
    char line[16] = "";
    assert_non_null(fgets(line, sizeof line, f));
    fclose(f);
    assert_string_equal(line, "previous\n");
}

static void test_format_of_path(void **state)
{
    (void)state;
    static const struct {
        const char *path;
        img_format want;
    } cases[] = {
        {"a.png", IMG_FORMAT_PNG},    {"dir.png/a.PNG", IMG_FORMAT_PNG}, {"a.ppm", IMG_FORMAT_PPM},
        {"a.Pnm", IMG_FORMAT_PPM},    {"a.pgm", IMG_FORMAT_PPM},         {"a.exr", IMG_FORMAT_MODULE},
        {"a.tif", IMG_FORMAT_MODULE}, {"png", IMG_FORMAT_MODULE},        {"x.png/a", IMG_FORMAT_MODULE},
        {"a.pfm", IMG_FORMAT_PFM},    {"a.PFM", IMG_FORMAT_PFM},         {"a.pfm.exr", IMG_FORMAT_MODULE},
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++)
        assert_int_equal(img_format_of(cases[i].path), cases[i].want);
    settings(true, -1);
    assert_int_equal(img_format_of("a.png"), IMG_FORMAT_MODULE);
    settings(false, -1);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test_setup_teardown(test_png_and_ppm_need_no_module, scratch_setup,
                                        scratch_teardown),
        cmocka_unit_test_setup_teardown(test_own_files_have_the_modules_pixels, scratch_setup,
                                        scratch_teardown),
        cmocka_unit_test_setup_teardown(test_pfm_holds_every_float, scratch_setup,
                                        scratch_teardown),
        cmocka_unit_test_setup_teardown(test_stream_order_changes_nothing, scratch_setup,
                                        scratch_teardown),
        cmocka_unit_test_setup_teardown(test_module_formats_stream, scratch_setup,
                                        scratch_teardown),
        cmocka_unit_test_setup_teardown(test_failed_write_names_the_file, scratch_setup,
                                        scratch_teardown),
        cmocka_unit_test(test_format_of_path),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
