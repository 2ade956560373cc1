/*
 * image_oiio.cpp — the one C++ file: the image API (image.h) over
 * OpenImageIO, built alone as the module csgtrace-image.so, which
 * host/output/image_loader.c loads on the first image call (image_module.h).  Its one
 * exported symbol is csgimg_module(); the rest is hidden.  Every exception
 * is caught here and turned into a false return with a message, so the C
 * side never sees C++.
 *
 * A file is written a run of rows at a time (open_file, file_rows,
 * close_file), as host/output/stream.c hands its bands over while the
 * image is rendered; 8-bit rows are encoded a strip at a time
 * (write_rows), so the writer never holds a copy of the whole image.
 *
 * Writing goes to the temporary file the loader made beside the target
 * (same extension, so OpenImageIO picks the same format), which the loader
 * renames over the target only once the file is complete.
 */
#include "image_module.h"
#include "../../comm/pixels.h"

#include <OpenImageIO/imagebuf.h>
#include <OpenImageIO/imagebufalgo.h>
#include <OpenImageIO/imageio.h>
#include <OpenImageIO/parallel.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <string>
#include <vector>

using namespace OIIO;

namespace {

void set_error(char *err, size_t size, const std::string &msg)
{
    if (err && size)
        std::snprintf(err, size, "%s", msg.c_str());
}

std::string extension_of(const std::string &path)
{
    size_t slash = path.find_last_of('/');
    size_t dot = path.find_last_of('.');
    if (dot == std::string::npos || (slash != std::string::npos && dot < slash))
        return "";
    std::string ext = path.substr(dot + 1);
    for (char &c : ext)
        c = (char)std::tolower((unsigned char)c);
    return ext;
}

/* Rows an 8-bit file is encoded and handed to OpenImageIO at a time: the
 * writer holds one strip (3 bytes a pixel), never a copy of the whole
 * image (host/memory.c counts it).  A multiple of TIFF's 32 rows a strip. */
constexpr int display_strip_rows = 64;

/* One strip of an 8-bit file, rows y0 .. y1 - 1, in the file's bytes
 * (comm/pixels.h: the conversion every 8-bit output gets), the rows spread
 * over OpenImageIO's thread pool. */
void display_strip(const float *rgb, int width, int y0, int y1, std::vector<unsigned char> &bytes)
{
    size_t row = (size_t)width * 3;
    bytes.resize(row * (size_t)(y1 - y0));
    parallel_for_range(int64_t(y0), int64_t(y1), [&](int64_t r0, int64_t r1) {
        pixels_to_rgb8(rgb + row * (size_t)r0, row * (size_t)(r1 - r0),
                       bytes.data() + row * (size_t)(r0 - y0));
    });
}

/* Rows y0 .. y1 - 1 (`rgb`: row y0's first value) written: an 8-bit
 * file's a strip at a time (display_strip), a float file's as they are. */
bool write_rows(ImageOutput &out, bool floats, const float *rgb, int width, int y0, int y1)
{
    if (floats)
        return out.write_scanlines(y0, y1, 0, TypeDesc::FLOAT, rgb);
    std::vector<unsigned char> bytes;
    size_t row = (size_t)width * 3;
    for (int s0 = y0; s0 < y1; s0 += display_strip_rows) {
        int s1 = std::min(y1, s0 + display_strip_rows);
        display_strip(rgb + row * (size_t)(s0 - y0), width, 0, s1 - s0, bytes);
        if (!out.write_scanlines(s0, s1, 0, TypeDesc::UINT8, bytes.data()))
            return false;
    }
    return true;
}

/* PNG: the Up filter on every row, then zlib's run-length strategy.  On
 * 8192x8192 renders that took a quarter of the time of OpenImageIO's
 * default (zlib level 6, each row's filter chosen among the five) for files
 * 6 to 25 % larger (docs/images.md).  A level of 0 to 9
 * ($CSGTRACE_PNG_LEVEL) asks for OpenImageIO's default at that zlib level
 * instead: 6 gives the files csgtrace wrote before, 9 the smallest. */
void set_png_options(ImageSpec &spec, int level)
{
    if (level >= 0 && level <= 9) {
        spec.attribute("png:compressionLevel", level);
        return;
    }
    spec.attribute("png:filter", 32); /* PNG_FILTER_UP */
    spec.attribute("compression", "rle");
}

/* OpenImageIO's writers that make no file: "null" (discards the pixels:
 * -o x.null wrote an empty file, exit 0) and "term" (draws on the
 * terminal). */
bool writes_no_file(const ImageOutput &out)
{
    std::string name = out.format_name();
    return name == "null" || name == "term";
}

/* An ImageOutput for path's format, or null with the message in err. */
std::unique_ptr<ImageOutput> output_for(const std::string &path, char *err, size_t esz)
{
    auto out = ImageOutput::create(path);
    if (!out) {
        set_error(err, esz,
                  path + ": cannot write this image format ('" + extension_of(path) +
                      "'): " + OIIO::geterror());
    } else if (writes_no_file(*out)) {
        set_error(err, esz,
                  path + ": cannot write this image format ('" + extension_of(path) +
                      "'): OpenImageIO's '" + out->format_name() + "' writer makes no file");
        out.reset();
    }
    return out;
}

/* A file being written (image_module.h: open_file .. close_file). */
struct module_file {
    std::unique_ptr<ImageOutput> out;
    std::string path; /* the target: the name messages give */
    int width;
    bool floats;
};

module_file *open_file(const char *path_c, const char *tmp, int width, int height, int png_level,
                       char *err, size_t esz)
{
    std::string path(path_c);
    auto out = output_for(path, err, esz);
    if (!out)
        return nullptr;
    bool floats = pixels_format_for(path_c) == PIXELS_FLOAT;
    ImageSpec spec(width, height, 3, floats ? TypeDesc::FLOAT : TypeDesc::UINT8);
    if (extension_of(path) == "png")
        set_png_options(spec, png_level);
    if (!out->open(tmp, spec)) {
        set_error(err, esz, path + ": " + out->geterror());
        return nullptr;
    }
    return new module_file{std::move(out), path, width, floats};
}

bool file_rows(module_file *f, int y0, int y1, const float *rgb, char *err, size_t esz)
{
    if (write_rows(*f->out, f->floats, rgb, f->width, y0, y1))
        return true;
    set_error(err, esz, f->path + ": " + f->out->geterror());
    return false;
}

bool close_file(module_file *f, char *err, size_t esz)
{
    std::unique_ptr<module_file> owned(f);
    if (f->out->close())
        return true;
    set_error(err, esz, f->path + ": " + f->out->geterror());
    return false;
}

struct free_deleter {
    void operator()(float *p) const { std::free(p); }
};

bool read_rgb(const char *path, float **rgb, int *width, int *height, char *err, size_t esz)
{
    ImageBuf buf(path);
    if (!buf.read(0, 0, true, TypeDesc::FLOAT)) {
        set_error(err, esz, std::string(path) + ": " + buf.geterror());
        return false;
    }
    const ImageSpec &spec = buf.spec();
    size_t pixels = (size_t)spec.width * (size_t)spec.height;
    std::unique_ptr<float[], free_deleter> data((float *)std::malloc(pixels * 3 * sizeof(float)));
    if (!data) {
        set_error(err, esz, std::string(path) + ": out of memory");
        return false;
    }
    ROI roi = buf.roi();
    roi.chbegin = 0;
    roi.chend = 3;
    if (spec.nchannels < 3) {
        /* grey: replicate */
        std::vector<float> grey(pixels * spec.nchannels);
        buf.get_pixels(buf.roi(), TypeDesc::FLOAT, grey.data());
        for (size_t i = 0; i < pixels; i++)
            data[3 * i] = data[3 * i + 1] = data[3 * i + 2] = grey[i * spec.nchannels];
    } else if (!buf.get_pixels(roi, TypeDesc::FLOAT, data.get())) {
        set_error(err, esz, std::string(path) + ": " + buf.geterror());
        return false;
    }
    *rgb = data.release();
    *width = spec.width;
    *height = spec.height;
    return true;
}

bool compare_files(const char *a, const char *b, double threshold, img_compare_result *r,
                   char *err, size_t esz)
{
    ImageBuf A(a), B(b);
    if (!A.read(0, 0, true, TypeDesc::FLOAT) || !B.read(0, 0, true, TypeDesc::FLOAT)) {
        set_error(err, esz, std::string("cannot read: ") + A.geterror() + B.geterror());
        return false;
    }
    /* ImageBufAlgo::compare does not flag a size mismatch: check it. */
    r->same_size = A.spec().width == B.spec().width && A.spec().height == B.spec().height &&
                   A.spec().nchannels == B.spec().nchannels;
    if (!r->same_size) {
        r->rmse = r->max_error = INFINITY;
        r->psnr = 0;
        r->pixels_over = (long)A.spec().width * A.spec().height;
        return true;
    }
    auto cr = ImageBufAlgo::compare(A, B, (float)threshold, (float)threshold);
    r->rmse = cr.rms_error;
    r->psnr = cr.PSNR;
    r->max_error = cr.maxerror;
    r->pixels_over = (long)cr.nfail;
    return true;
}

/* body() with every exception turned into false and "SUBJECT: what" in err
 * (formatted without allocating, so the handlers themselves cannot throw). */
template <class F> bool guarded(const char *subject, const char *doing, char *err, size_t esz, F body)
{
    const char *sep = subject ? ": " : "";
    subject = subject ? subject : "";
    try {
        return body();
    } catch (const std::exception &e) {
        if (err && esz)
            std::snprintf(err, esz, "%s%s%s", subject, sep, e.what());
    } catch (...) {
        if (err && esz)
            std::snprintf(err, esz, "%s%sunknown error %s", subject, sep, doing);
    }
    return false;
}

void *module_open_file(const char *path, const char *tmp, int width, int height, int png_level,
                       char *err, size_t esz)
{
    module_file *f = nullptr;
    guarded(path, "opening the image", err, esz, [&] {
        f = open_file(path, tmp, width, height, png_level, err, esz);
        return f != nullptr;
    });
    return f;
}

bool module_write_rows(void *f, int y0, int y1, const float *rgb, char *err, size_t esz)
{
    module_file *file = static_cast<module_file *>(f);
    return guarded(file->path.c_str(), "writing the image", err, esz,
                   [&] { return file_rows(file, y0, y1, rgb, err, esz); });
}

bool module_close_file(void *f, char *err, size_t esz)
{
    module_file *file = static_cast<module_file *>(f);
    char path[1024]; /* (close_file frees the file; copied without allocating) */
    std::snprintf(path, sizeof path, "%s", file->path.c_str());
    return guarded(path, "writing the image", err, esz,
                   [&] { return close_file(file, err, esz); });
}

bool module_read_rgb(const char *path, float **rgb, int *width, int *height, char *err,
                     size_t esz)
{
    *rgb = nullptr;
    return guarded(path, "reading the image", err, esz,
                   [&] { return read_rgb(path, rgb, width, height, err, esz); });
}

bool module_compare_files(const char *a, const char *b, double threshold, img_compare_result *r,
                          char *err, size_t esz)
{
    return guarded(nullptr, "comparing images", err, esz,
                   [&] { return compare_files(a, b, threshold, r, err, esz); });
}

bool module_can_write(const char *path, char *err, size_t esz)
{
    return guarded(path, "choosing the image format", err, esz,
                   [&] { return output_for(path, err, esz) != nullptr; });
}

const img_module module_table = {IMG_MODULE_ABI,       sizeof(img_module),   module_open_file,
                                 module_write_rows,    module_close_file,    module_read_rgb,
                                 module_compare_files, module_can_write};

} // namespace

extern "C" __attribute__((visibility("default"))) const img_module *csgimg_module(void)
{
    return &module_table;
}
