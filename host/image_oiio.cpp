/*
 * image_oiio.cpp — the one C++ file: the image API (image.h) over
 * OpenImageIO, built alone as the module csgtrace-image.so, which
 * host/image_loader.c loads on the first image call (image_module.h).  Its one
 * exported symbol is csgimg_module(); the rest is hidden.  Every exception
 * is caught here and turned into a false return with a message, so the C
 * side never sees C++.
 *
 * Writing goes to a temporary file beside the target (same extension, so
 * OpenImageIO picks the same format) and is renamed over the target only
 * once the file is complete.
 */
#include "image_module.h"

#include <OpenImageIO/imagebuf.h>
#include <OpenImageIO/imagebufalgo.h>
#include <OpenImageIO/imageio.h>

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <string>
#include <unistd.h>
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

bool is_float_format(const std::string &ext)
{
    return ext == "exr" || ext == "hdr" || ext == "pfm";
}

/* The display encoding of 8-bit files: the sRGB transfer curve, which is
 * what POV-Ray 3.7 writes to PNG with assumed_gamma 1 and its default file
 * gamma (measured: all 256 levels agree). */
float encode_display(float v)
{
    if (!(v > 0.0f))
        return 0.0f;
    if (v >= 1.0f)
        return 1.0f;
    if (v <= 0.0031308f)
        return 12.92f * v;
    return 1.055f * std::pow(v, 1.0f / 2.4f) - 0.055f;
}

std::string temp_name_for(const std::string &path)
{
    size_t slash = path.find_last_of('/');
    std::string dir = slash == std::string::npos ? "" : path.substr(0, slash + 1);
    std::string base = slash == std::string::npos ? path : path.substr(slash + 1);
    std::string ext = extension_of(path);
    return dir + "." + base + ".tmp" + std::to_string((long)getpid()) + (ext.empty() ? "" : "." + ext);
}

bool write_rgb(const char *path_c, const float *rgb, int width, int height, char *err, size_t esz)
{
    std::string path(path_c);
    std::string ext = extension_of(path);
    std::string tmp = temp_name_for(path);
    auto out = ImageOutput::create(path);
    if (!out) {
        set_error(err, esz, path + ": cannot write this image format ('" + ext + "'): " + OIIO::geterror());
        return false;
    }
    bool linear = is_float_format(ext);
    ImageSpec spec(width, height, 3, linear ? TypeDesc::FLOAT : TypeDesc::UINT8);
    std::vector<float> pixels((size_t)width * (size_t)height * 3);
    for (size_t i = 0; i < pixels.size(); i++)
        pixels[i] = linear ? rgb[i] : encode_display(rgb[i]);
    if (!out->open(tmp, spec)) {
        set_error(err, esz, path + ": " + out->geterror());
        std::remove(tmp.c_str());
        return false;
    }
    bool ok = out->write_image(TypeDesc::FLOAT, pixels.data());
    std::string werr = ok ? "" : out->geterror();
    ok = out->close() && ok;
    if (!ok) {
        set_error(err, esz, path + ": " + (werr.empty() ? out->geterror() : werr));
        std::remove(tmp.c_str());
        return false;
    }
    if (std::rename(tmp.c_str(), path.c_str()) != 0) {
        set_error(err, esz, path + ": cannot rename the finished image: " + std::strerror(errno));
        std::remove(tmp.c_str());
        return false;
    }
    return true;
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

bool module_write_rgb(const char *path, const float *rgb, int width, int height, char *err,
                      size_t esz)
{
    return guarded(path, "writing the image", err, esz,
                   [&] { return write_rgb(path, rgb, width, height, err, esz); });
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

const img_module module_table = {IMG_MODULE_ABI, sizeof(img_module), module_write_rgb,
                                 module_read_rgb, module_compare_files};

} // namespace

extern "C" __attribute__((visibility("default"))) const img_module *csgimg_module(void)
{
    return &module_table;
}
