/*
 * test_pigment.c — the patterns (noise, shapes, blocks, spirals) against
 * POV-Ray 3.7 itself: each pigment below, with the colour map [0 rgb 0]
 * [1 rgb 1] (so red is the pattern's value after its wave; brick and
 * hexagon list their colours instead: 0 and 1, 0, 0.5 and 1), evaluated
 * at five fixed points by workers/pigment.c (double build) and by POV-Ray 3.7.0.10, whose values
 * are written here.  They were printed by POV-Ray from
 * tests/pigment_reference.pov (`povray +Itests/pigment_reference.pov -D
 * +W8 +H8 +GD`; its pigment functions evaluate exactly the pigment at the
 * point), to 12 decimals; POV-Ray keeps colours in single precision, so a
 * value agrees within 1e-6.  The scenes go through the parser and the
 * flattener, so the keywords, defaults and transforms are covered too.
 * Plus the noise's own properties (range, continuity, one octave of
 * turbulence), the limit on maps of maps, and the export of every case
 * read back to the same values; the keywords' errors are in
 * test_language.c.
 */
#define CSG_DOUBLE 1
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "../csg/device/intersect.h"
#include "../csg/export_pov.h"
#include "../csg/flatten.h"
#include "../csg/load.h"
#include "../workers/engine.h"
#include "../workers/noise.h"
#include "../workers/pigment.h"

/* The points, and POV-Ray's value at each of them, of every pigment. */
static const double points[5][3] = {
    {0.3, 1.7, -2.2},
    {-3.41, 0.05, 7.9},
    {12.5, -8.25, 0.6},
    {-0.7, -0.2, -0.45},
    {100.3, 20.1, -55.7}};

static const struct {
    const char *pigment;
    double povray[5];
} cases[] = {
    {"bozo",
     {0.528851449490, 0.724114954472, 0.727150678635, 0.555078923702, 0.539341330528}},
    {"bozo noise_generator 1",
     {0.527186393738, 0.925800621510, 0.931997776031, 0.580727517605, 0.548600614071}},
    {"bozo noise_generator 3",
     {0.670296311378, 0.546854496002, 0.559027194977, 0.459163755178, 0.669627606869}},
    {"spotted turbulence 0.5 scale 0.7",
     {0.538444280624, 0.484016150236, 0.477337300777, 0.658042490482, 0.680321455002}},
    {"wood turbulence 0.1",
     {0.605873703957, 0.804433584213, 0.638092637062, 0.067083999515, 0.837125599384}},
    {"wood scale 0.3",
     {0.491649001837, 0.735557019711, 0.153874665499, 0.853366613388, 0.045575946569}},
    {"marble turbulence 1.2 octaves 3 omega 0.7 lambda 2.5",
     {0.402000218630, 0.081691287458, 0.127517119050, 0.318404793739, 0.990538895130}},
    {"granite scale 2",
     {0.282916545868, 0.590719163418, 0.211417734623, 0.646849811077, 0.469822615385}},
    {"granite noise_generator 1",
     {0.267535001040, 0.199360534549, 0.253691822290, 0.295175045729, 0.650469541550}},
    {"agate",
     {0.729962885380, 0.423948168755, 0.473819673061, 0.970517039299, 0.722189784050}},
    {"agate agate_turb 0.5 turbulence 0.2 noise_generator 3",
     {0.900897145271, 0.836548805237, 0.845926761627, 0.761235415936, 0.468741208315}},
    {"bozo turbulence <0.3, 0.6, 0.9> sine_wave frequency 2 phase 0.1",
     {0.934915482998, 0.653127372265, 0.093010440469, 0.961340904236, 0.794089198112}},
    {"marble turbulence 0.5 scallop_wave noise_generator 1",
     {0.490000784397, 0.978150606155, 0.577757954597, 0.120450869203, 0.647296786308}},
    {"wood turbulence <0.2, 0.3, 0> octaves 4 poly_wave 2",
     {0.208193942904, 0.022794434801, 0.814303457737, 0.185562089086, 0.250637799501}},
    {"gradient x turbulence 0.4 triangle_wave",
     {0.671694397926, 0.257805109024, 0.673576414585, 0.881619453430, 0.575539112091}},
    {"bozo translate 0.3 turbulence 0.4 rotate 20 * y cubic_wave",
     {0.529413759708, 0.429327726364, 0.584755599499, 0.727337479591, 0.186869129539}},
    {"granite turbulence 0.3 lambda 3 omega 0.4 octaves 2 scale <1, 2, 3>",
     {0.525456905365, 0.701827287674, 0.223300337791, 0.256050586700, 0.349002689123}},
    {"wrinkles",
     {0.574601292610, 0.867985963821, 0.729482054710, 0.692114233971, 0.514997661114}},
    {"wrinkles noise_generator 1 scale 0.4",
     {0.660387158394, 0.254616647959, 0.432014137506, 0.705557465553, 0.292912900448}},
    {"bumps turbulence 0.2",
     {0.536546945572, 0.724716365337, 0.753551900387, 0.535814523697, 0.574906051159}},
    {"radial frequency 3 rotate <10, 20, 30>",
     {0.387449413538, 0.898581564426, 0.665404319763, 0.055432729423, 0.057007413357}},
    {"onion scale 2.5",
     {0.118570514023, 0.441873908043, 0.995631754398, 0.342344850302, 0.590282261372}},
    {"leopard scale 0.3",
     {0.040565200150, 0.457914501429, 0.030641678721, 0.607854485512, 0.019780918956}},
    {"planar scale 8",
     {0.787500023842, 0.993749976158, 0.000000000000, 0.975000023842, 0.000000000000}},
    {"boxed scale 20",
     {0.889999985695, 0.605000019073, 0.375000000000, 0.964999973774, 0.000000000000}},
    {"cylindrical scale 10 turbulence 0.5",
     {0.488026827574, 0.309821695089, 0.000000000000, 0.362002491951, 0.000000000000}},
    {"gradient x pigment_map { [0 bozo color_map { [0 rgb 0] [1 rgb 1] }] [1 wood "
     "turbulence 0.1 scale 0.5 color_map { [0 rgb 0] [1 rgb 1] }] } turbulence 0.3 "
     "scale 7",
     {0.737125933170, 0.667318940163, 0.792326629162, 0.247402906418, 0.380331963301}},
    {"marble pigment_map { [0.2 rgb 0.1] [0.5 granite pigment_map { [0 rgb 0] [1 "
     "agate color_map { [0 rgb 0] [1 rgb 1] }] }] [0.9 rgb 0.9] } scale 3",
     {0.100000001490, 0.090116113424, 0.114621192217, 0.289032906294, 0.824699282646}},
    {"crackle",
     {0.105890467763, 0.083837546408, 0.330896735191, 0.615848302841, 0.127060428262}},
    {"crackle solid",
     {0.470837652683, 0.459566056728, 0.547981202602, 0.608818233013, 0.445237904787}},
    {"crackle metric 1 form <0.5, 0.3, 0.1> offset 0.2",
     {0.764239072800, 1.000000000000, 0.860600590706, 0.906964063644, 1.000000000000}},
    {"crackle metric 3 form <-0.5, 1, 0.2> scale 0.4 turbulence 0.3",
     {0.523133575916, 0.599838018417, 0.709638297558, 0.785753667355, 0.801226437092}},
    {"crackle solid noise_generator 1 scale 0.3 offset 0.5",
     {0.281486570835, 0.461489737034, 0.302077710629, 0.545371532440, 0.527392625809}},
    {"spiral1 5",
     {0.225484132767, 0.097098268569, 0.725344598293, 0.498869627714, 0.002182263415}},
    {"spiral2 3 scale 0.7",
     {0.905007898808, 0.114835344255, 0.685568928719, 0.960084617138, 0.168379858136}},
    {"spiral1 -2 turbulence 0.3 octaves 3 sine_wave frequency 2 phase 0.2",
     {0.996748268604, 0.999238729477, 0.169951826334, 0.856558024883, 0.057894591242}},
    {"spiral2 7 turbulence <0.4, 0.2, 0.1> noise_generator 1 rotate <10, 20, 30>",
     {0.634373664856, 0.190073817968, 0.463649123907, 0.505114197731, 0.244078308344}},
    {"brick rgb 0, rgb 1 brick_size <0.5, 0.3, 0.4> mortar 0.1",
     {0.000000000000, 1.000000000000, 1.000000000000, 0.000000000000, 0.000000000000}},
    {"brick rgb 0, rgb 1 scale 0.05 turbulence 0.2",
     {1.000000000000, 1.000000000000, 1.000000000000, 1.000000000000, 0.000000000000}},
    {"hexagon rgb 0, rgb 0.5, rgb 1 scale 0.4 rotate 30 * y",
     {0.000000000000, 0.000000000000, 0.500000000000, 0.000000000000, 0.500000000000}},
    {"hexagon rgb 0, rgb 0.5, rgb 1 rotate <20, 40, 60> turbulence 0.3",
     {0.000000000000, 1.000000000000, 0.500000000000, 0.000000000000, 0.500000000000}},
    {"hexagon rgb 0, rgb 0.5, rgb 1 scale 0.13",
     {1.000000000000, 1.000000000000, 0.000000000000, 0.500000000000, 1.000000000000}},
    {"hexagon rgb 0, rgb 0.5, rgb 1 scale 0.021 rotate 7 * y",
     {0.500000000000, 0.000000000000, 0.500000000000, 0.000000000000, 0.500000000000}},
    {"hexagon rgb 0, rgb 0.5, rgb 1 scale 0.0517",
     {1.000000000000, 0.500000000000, 1.000000000000, 1.000000000000, 1.000000000000}},
    {"brick rgb 0, rgb 1 scale 0.0831 rotate <30, 60, 10>",
     {0.000000000000, 1.000000000000, 1.000000000000, 1.000000000000, 0.000000000000}},
    {"pigment_pattern { bozo color_map { [0 rgb <1, 0.2, 0>] [1 rgb <0, 0.5, 1>] } "
     "scale 0.5 }",
     {0.411178946495, 0.410006582737, 0.411937236786, 0.409927189350, 0.411115705967}},
    {"pigment_pattern { gradient x pigment_map { [0 rgb <0.3, 0.9, 0.1>] [1 wood "
     "color_map { [0 rgb 1] [1 rgb <0, 0, 1>] }] } scale 3 } turbulence 0.2 sine_wave",
     {0.223235055804, 0.050255510956, 0.024439185858, 0.189993575215, 0.008261550218}},
    {"pigment_pattern { hexagon rgb <1, 0, 0>, rgb <0, 1, 0>, rgb <0, 0, 1> scale 0.6 }",
     {0.588999986649, 0.114000000060, 0.588999986649, 0.588999986649, 0.114000000060}},
};

/* The flat scene (double precision) of scene text; the scene itself too
 * when s is not NULL. */
static csg_blob load_text(const char *text, csg_scene *keep)
{
    csg_scene s;
    csg_diag d = {0};
    if (!csg_load_string("pigment.pov", text, strlen(text), NULL, &s, &d))
        fail_msg("parse: %s\n%s", d.message, text);
    csg_flatten_opts o = {4, 4, 0, -1, 1, 0};
    csg_blob b;
    if (!engine_double.flatten(&s, &o, &b, &d))
        fail_msg("flatten: %s\n%s", d.message, text);
    if (keep)
        *keep = s;
    else
        csg_scene_free(&s);
    return b;
}

/* The text of a plane with pigment `pig` (and the grey map unless it has
 * a pigment map or, a block pattern, its colours), under #version
 * `version`. */
static void pigment_scene(char *text, size_t size, const char *pig, const char *version)
{
    bool listed = strncmp(pig, "brick", 5) == 0 || strncmp(pig, "hexagon", 7) == 0;
    const char *map =
        strstr(pig, "pigment_map") || listed ? "" : " color_map { [0 rgb 0] [1 rgb 1] }";
    snprintf(text, size, "#version %s;\nplane { y, 0 pigment { %s%s } }\n", version, pig, map);
}

static csg_blob load_pigment(const char *pig)
{
    char text[1024];
    pigment_scene(text, sizeof text, pig, "3.7");
    return load_text(text, NULL);
}

/* The value of the plane's pigment at point p (red of the grey map). */
static double value_at(const csg_blob *b, const double p[3])
{
    const unsigned char *bytes = b->bytes;
    const csg_blob_header *h = b->bytes;
    csg_view v = csg_blob_view(bytes);
    const csg_material *mats = (const csg_material *)(bytes + h->off_materials);
    const csg_map_color *maps = (const csg_map_color *)(bytes + h->off_maps);
    pigment_color c = pigment_at_double(mats, &mats[v.prims[0].material], maps, NULL, CSG_SURF_NONE,
                                        v3(p[0], p[1], p[2]), 0.0);
    return c.color.x;
}

static void test_against_povray(void **state)
{
    (void)state;
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        csg_blob b = load_pigment(cases[i].pigment);
        for (int k = 0; k < 5; k++) {
            double got = value_at(&b, points[k]);
            if (fabs(got - cases[i].povray[k]) > 1e-6)
                fail_msg("pigment { %s } at <%g, %g, %g>: %.12f, POV-Ray %.12f", cases[i].pigment,
                         points[k][0], points[k][1], points[k][2], got, cases[i].povray[k]);
        }
        free(b.bytes);
    }
}

/* The noise itself: in [0, 1] for every generator, continuous across
 * lattice planes on both sides of 0 (POV-Ray's range fix), and one
 * octave of turbulence is the noise (stretched for generators 2 and 3). */
static void test_noise_properties(void **state)
{
    (void)state;
    uint32_t r = 12345;
    for (int gen = 1; gen <= 3; gen++) {
        for (int i = 0; i < 2000; i++) {
            double p[3];
            for (int k = 0; k < 3; k++) {
                r = r * 1103515245u + 12345u;
                p[k] = ((double)(r >> 8) / (double)(1u << 24) - 0.5) * 100.0;
            }
            double v = noise_value(p, gen);
            if (!(v >= 0.0 && v <= 1.0))
                fail_msg("generator %d at <%g, %g, %g>: %g", gen, p[0], p[1], p[2], v);
            noise_turb one = {1, 0.5, 2.0};
            double t = noise_turbulence(p, &one, gen), n = gen > 1 ? 2.0 * v - 0.5 : v;
            n = n < 0.0 ? 0.0 : n > 1.0 ? 1.0 : n;
            if (t != n)
                fail_msg("generator %d: one octave %g, noise %g", gen, t, n);
        }
        static const double planes[] = {-7.0, -1.0, 0.0, 1.0, 3.0};
        for (size_t i = 0; i < sizeof planes / sizeof planes[0]; i++) {
            double a[3] = {planes[i] - 1e-9, 0.3, 0.6}, b[3] = {planes[i] + 1e-9, 0.3, 0.6};
            if (fabs(noise_value(a, gen) - noise_value(b, gen)) > 1e-6)
                fail_msg("generator %d jumps at x = %g", gen, planes[i]);
        }
    }
    assert_true(noise_triangle(0.25) == 0.5 && noise_triangle(0.75) == 0.5);
    assert_true(noise_triangle(-0.25) == 0.5);
    assert_true(fabs(noise_cycloidal(0.25) - 1.0) < 1e-12);
    assert_true(fabs(noise_cycloidal(-0.25) + 1.0) < 1e-12);
}

/* Maps of maps declared from the same pigment double at every level: the
 * flattener stops at its limit with a message instead of exhausting
 * memory; below it, the scene flattens. */
static void test_pigment_map_limit(void **state)
{
    (void)state;
    const char *fmt = "#declare P = pigment { bozo }\n"
                      "#declare I = 0;\n"
                      "#while (I < %d)\n"
                      "  #declare P = pigment { bozo pigment_map { [0 P] [1 P] } }\n"
                      "  #declare I = I + 1;\n"
                      "#end\n"
                      "sphere { 0, 1 pigment { P } }\n";
    for (int levels = 8; levels <= 21; levels += 13) {
        char text[512];
        snprintf(text, sizeof text, fmt, levels);
        csg_scene s;
        csg_diag d = {0};
        if (!csg_load_string("maps.pov", text, strlen(text), NULL, &s, &d))
            fail_msg("parse: %s", d.message);
        csg_flatten_opts o = {4, 4, 0, -1, 1, 0};
        csg_blob b;
        bool ok = engine_double.flatten(&s, &o, &b, &d);
        csg_scene_free(&s);
        if (levels == 8) {
            assert_true(ok); /* 510 pigments */
            free(b.bytes);
        } else {
            assert_false(ok); /* 2^22 - 2 */
            assert_non_null(strstr(d.message, "pigment maps hold more than"));
        }
    }
}

/* export writes every pigment so that it reads back the same: each case
 * under #version 3.1 (noise generator 1 unless the pigment says), exported
 * (the export says #version 3.7, so the generator must be written),
 * parsed again: the same value at every point, to the bit. */
static void test_export_round_trip(void **state)
{
    (void)state;
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        char text[1024];
        pigment_scene(text, sizeof text, cases[i].pigment, "3.1");
        csg_scene s;
        csg_blob a = load_text(text, &s);
        char *out = NULL;
        size_t len = 0;
        FILE *f = open_memstream(&out, &len);
        csg_diag d = {0};
        assert_non_null(f);
        bool ok = csg_export_pov(&s, f, false, &d);
        fclose(f);
        csg_scene_free(&s);
        if (!ok)
            fail_msg("export %s: %s", cases[i].pigment, d.message);
        csg_blob b = load_text(out, NULL);
        for (int k = 0; k < 5; k++) {
            double va = value_at(&a, points[k]), vb = value_at(&b, points[k]);
            if (va != vb)
                fail_msg("pigment { %s } at point %d: %.17g, exported %.17g", cases[i].pigment, k,
                         va, vb);
        }
        free(out);
        free(a.bytes);
        free(b.bytes);
    }
}

/* Far from the origin (#39): crackle's cubes and the noise's cells are
 * ints; a point beyond the int range, or at its edge where a neighbour's
 * cell is past it, converts and adds in range (UBSan: float-cast-overflow,
 * signed overflow) and the value stays in [0, 1]. */
static void test_far_from_origin(void **state)
{
    (void)state;
    static const double far[][3] = {
        {2147483646.5, 0.3, 0.6}, {-2147483647.5, -2147483647.5, 0.2}, {1e30, -1e30, 3},
        {0.3, 1e300, -1e300},     {2147483647.0, 2147483647.0, 2147483647.0},
    };
    static const char *const pigs[] = {"crackle", "crackle solid", "crackle metric 3",
                                       "crackle solid noise_generator 3", "bozo noise_generator 3",
                                       "bozo noise_generator 1"};
    for (size_t i = 0; i < sizeof pigs / sizeof pigs[0]; i++) {
        csg_blob b = load_pigment(pigs[i]);
        for (size_t k = 0; k < sizeof far / sizeof far[0]; k++) {
            double v = value_at(&b, far[k]);
            if (!(v >= 0.0 && v <= 1.0))
                fail_msg("pigment { %s } at <%g, %g, %g>: %g", pigs[i], far[k][0], far[k][1],
                         far[k][2], v);
        }
        free(b.bytes);
    }
    for (int gen = 1; gen <= 3; gen++)
        for (size_t k = 0; k < sizeof far / sizeof far[0]; k++) {
            double v = noise_value(far[k], gen);
            assert_true(v >= 0.0 && v <= 1.0);
        }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_against_povray),
        cmocka_unit_test(test_noise_properties),
        cmocka_unit_test(test_pigment_map_limit),
        cmocka_unit_test(test_export_round_trip),
        cmocka_unit_test(test_far_from_origin),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
