/*
 * pixels.h — the pixel formats of the results a worker sends (protocol.h)
 * and the one conversion from linear float RGB to the bytes of an 8-bit
 * image file, shared by the workers (which send those bytes when the
 * output is an 8-bit file), the master (which stores them) and the image
 * writer (host/output/image_oiio.cpp: this header compiles as C++ too).
 *
 * An 8-bit file's byte for a linear value v is pixels_srgb_byte(v):
 * pixels_srgb_encode (clamp to [0, 1], the sRGB curve, as POV-Ray 3.7
 * writes PNG with assumed_gamma 1), then e * 255 + 0.5 truncated.  Every
 * 8-bit file is encoded so, whoever writes it (PNG and PPM by csgtrace,
 * the other formats through OpenImageIO, which is handed the bytes): the
 * same value gives the same byte on a worker, in the journal and in the
 * file.  (OpenImageIO's own float to uint8 conversion agrees but for one
 * value, x * 255 = 0.49999997, which its SIMD lanes round to 0 and its
 * scalar tail to 1: it is never asked.)
 */
#ifndef COMM_PIXELS_H
#define COMM_PIXELS_H

#include <math.h>
#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>
#include <strings.h>

#ifdef __cplusplus
extern "C" {
#endif

/* What a RESULT part carries a pixel (proto_setup.pixels,
 * proto_result.pixels). */
enum pixels_format {
    PIXELS_FLOAT = 0, /* 3 linear floats: float files (EXR), no file      */
    PIXELS_RGB8 = 1,  /* 3 bytes: what an 8-bit file holds                */
    PIXELS_RGB8Z = 2  /* RGB8's bytes compressed, one Zstandard frame a part
                         (--compress: comm/pixels_z.h)                  */
};

/* Is `format` one of the 8-bit ones (what an 8-bit file holds, compressed
 * or not on the wire)? */
static inline bool pixels_is_rgb8(int format)
{
    return format == PIXELS_RGB8 || format == PIXELS_RGB8Z;
}

/* Bytes a pixel in `format` (PIXELS_RGB8Z: once decompressed). */
static inline size_t pixels_bytes(int format)
{
    return pixels_is_rgb8(format) ? 3 : 3 * sizeof(float);
}

static inline const char *pixels_format_name(int format)
{
    return format == PIXELS_RGB8Z ? "rgb8z" : format == PIXELS_RGB8 ? "rgb8" : "float";
}

/* The display encoding of 8-bit files: the sRGB transfer curve (POV-Ray
 * 3.7's PNG with assumed_gamma 1: all 256 levels measured to agree). */
static inline float pixels_srgb_encode(float v)
{
    if (!(v > 0.0f))
        return 0.0f;
    if (v >= 1.0f)
        return 1.0f;
    if (v <= 0.0031308f)
        return 12.92f * v;
    return 1.055f * powf(v, 1.0f / 2.4f) - 0.055f;
}

/* The byte an 8-bit file holds for linear v. */
static inline uint8_t pixels_srgb_byte(float v)
{
    return (uint8_t)(int)(pixels_srgb_encode(v) * 255.0f + 0.5f);
}

/* The scene's output gamma (csg/device/flat.h, enum csg_output_gamma,
 * whose values these are: this header compiles as C++ too). */
enum { PIXELS_GAMMA_SRGB = 0, PIXELS_GAMMA_POWER = 1, PIXELS_GAMMA_DIRECT = 2 };

/* The linear value a pixel of colour v (a channel, finite) is stored as,
 * so that pixels_srgb_byte gives POV-Ray 3.7's byte for the scene's gamma
 * handling (its PNG: the sRGB curve of the working gamma's decoding):
 *   PIXELS_GAMMA_SRGB   v (assumed_gamma 1): unchanged;
 *   PIXELS_GAMMA_POWER  POV-Ray's power curve: powf(max(v, 0), 1 / e),
 *                       e = 1 / gamma in float (PowerLawGammaCurve);
 *   PIXELS_GAMMA_DIRECT the inverse of the sRGB curve at v (the working
 *                       gamma is the file's: POV-Ray writes floor(clip(v) *
 *                       255 + 0.5)), kept within the floats whose byte is
 *                       that one, so the byte is POV-Ray's exactly.
 * A float file (EXR) holds this linear value.  Never above FLT_MAX. */
float pixels_scene_linear(float v, int gamma_mode, float gamma);

/* n linear values converted to bytes (out may not alias rgb): each
 * pixels_srgb_byte's, faster. */
void pixels_to_rgb8(const float *rgb, size_t n, uint8_t *out);

/* A linear value whose byte is b (pixels_srgb_byte gives b back): what
 * the master keeps for a byte received, so the writer turns it into that
 * very byte. */
float pixels_linear_of(uint8_t b);
/* pixels_linear_of of a rectangle's bytes (packed in src, 3 a pixel) into
 * the rectangle x, y, width x height of a float image `image_width` pixels
 * wide (the master stores every received 8-bit tile so).  Visible to every
 * thread when it returns; the image is not read into the cache. */
void pixels_store_bytes_rect(float *image, int image_width, int x, int y, int width, int height,
                             const uint8_t *src);

/* The format of output file `path`, by its extension (any case): PIXELS_FLOAT
 * for the float formats (exr, hdr, pfm), PIXELS_RGB8 for every other (8-bit)
 * one; NULL (no file): PIXELS_FLOAT.  The one list of float formats: the
 * writer (image_oiio.cpp), the results and the memory estimate use it. */
/* Is the extension of `path` (after the last '.' of its last component)
 * one of names[0..n), in any case? */
static inline bool pixels_extension_in(const char *path, const char *const *names, size_t n)
{
    const char *slash = strrchr(path, '/');
    const char *dot = strrchr(path, '.');
    if (!dot || (slash && dot < slash))
        return false;
    for (size_t i = 0; i < n; i++)
        if (strcasecmp(dot + 1, names[i]) == 0)
            return true;
    return false;
}

static inline int pixels_format_for(const char *path)
{
    static const char *const floats[] = {"exr", "hdr", "pfm"};
    if (!path || pixels_extension_in(path, floats, sizeof floats / sizeof floats[0]))
        return PIXELS_FLOAT;
    return PIXELS_RGB8;
}

#ifdef __cplusplus
}
#endif

#endif
