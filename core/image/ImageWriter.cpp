#include "core/image/ImageWriter.h"

#include <ImfChannelList.h>
#include <OpenEXRConfig.h>
#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <ImfMultiPartOutputFile.h>
#include <ImfOutputFile.h>
#include <ImfOutputPart.h>
#include <ImfPartType.h>
#include <png.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <functional>

#include "core/base/Error.h"

namespace hvx::core {

namespace {
std::string temporaryName(const std::string& path) { return path + ".partial"; }

void commit(const std::string& tmp, const std::string& path) {
    if (std::rename(tmp.c_str(), path.c_str()) != 0) {
        std::remove(tmp.c_str());
        throw Error(path + ": cannot write image");
    }
}
}  // namespace

void ImageWriter::write(const RenderImage& image, const std::string& path) {
    const std::string ext = std::filesystem::path(path).extension().string();
    if (ext == ".png") writePng(image, path);
    else if (ext == ".exr") writeExr(image, path);
    else throw Error(path + ": output must end in .png or .exr");
}

namespace {
/// Writes rows of `channels` 8-bit samples (1: grey, 4: RGBA) as a PNG, under a temporary name.
void writePngRows(int width, int height, int channels, const std::function<void(int, png_byte*)>& fillRow,
                  const std::string& path) {
    const std::string tmp = temporaryName(path);
    FILE* f = std::fopen(tmp.c_str(), "wb");
    if (!f) throw Error(path + ": cannot write image");
    png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, nullptr, nullptr, nullptr);
    png_infop info = png ? png_create_info_struct(png) : nullptr;
    if (!png || !info || setjmp(png_jmpbuf(png))) {
        png_destroy_write_struct(&png, &info);
        std::fclose(f);
        std::remove(tmp.c_str());
        throw Error(path + ": PNG encoding failed (disk full?)");
    }
    png_init_io(png, f);
    png_set_IHDR(png, info, png_uint_32(width), png_uint_32(height), 8,
                 channels == 1 ? PNG_COLOR_TYPE_GRAY : channels == 3 ? PNG_COLOR_TYPE_RGB : PNG_COLOR_TYPE_RGBA, PNG_INTERLACE_NONE,
                 PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
    png_write_info(png, info);
    std::vector<png_byte> row(std::size_t(width) * std::size_t(channels));
    for (int y = 0; y < height; ++y) {
        fillRow(y, row.data());
        png_write_row(png, row.data());
    }
    png_write_end(png, nullptr);
    png_destroy_write_struct(&png, &info);
    if (std::fclose(f) != 0) {
        std::remove(tmp.c_str());
        throw Error(path + ": cannot write image (disk full?)");
    }
    commit(tmp, path);
}
}  // namespace

void ImageWriter::writePng(const RenderImage& image, const std::string& path) {
    auto encode = [](float v) {
        v = std::clamp(v, 0.0f, 1.0f);
        const float s = v <= 0.0031308f ? 12.92f * v : 1.055f * std::pow(v, 1.0f / 2.4f) - 0.055f;
        return png_byte(std::lround(s * 255.0f));
    };
    writePngRows(image.width, image.height, 4, [&](int y, png_byte* row) {
        for (int x = 0; x < image.width; ++x) {
            // Premultiplied colour over the black background a reading room expects.
            const glm::vec4 c = image.rgba[std::size_t(y) * std::size_t(image.width) + std::size_t(x)];
            row[std::size_t(x) * 4 + 0] = encode(c.r);
            row[std::size_t(x) * 4 + 1] = encode(c.g);
            row[std::size_t(x) * 4 + 2] = encode(c.b);
            row[std::size_t(x) * 4 + 3] = 255;
        }
    }, path);
}

void ImageWriter::writeGreyPng(int width, int height, const std::vector<std::uint8_t>& grey, const std::string& path) {
    if (grey.size() != std::size_t(width) * std::size_t(height)) throw Error(path + ": grey image of the wrong size");
    writePngRows(width, height, 1, [&](int y, png_byte* row) {
        std::copy_n(grey.data() + std::size_t(y) * std::size_t(width), std::size_t(width), row);
    }, path);
}

void ImageWriter::writeRgbPng(int width, int height, const std::vector<std::uint8_t>& rgb, const std::string& path) {
    if (rgb.size() != 3 * std::size_t(width) * std::size_t(height)) throw Error(path + ": RGB image of the wrong size");
    writePngRows(width, height, 3, [&](int y, png_byte* row) {
        std::copy_n(rgb.data() + 3 * std::size_t(y) * std::size_t(width), 3 * std::size_t(width), row);
    }, path);
}

namespace {
Imf::Header exrHeader(const RenderImage& image, const std::string& partName) {
    Imf::Header header(image.width, image.height);
    for (const char* c : {"R", "G", "B", "A", "Z"}) header.channels().insert(c, Imf::Channel(Imf::FLOAT));
    if (!partName.empty()) {
        header.setName(partName);
        header.setType(Imf::SCANLINEIMAGE);
    }
    return header;
}

Imf::FrameBuffer exrFrameBuffer(const RenderImage& image) {
    Imf::FrameBuffer fb;
    const std::size_t px = sizeof(glm::vec4);
    char* base = reinterpret_cast<char*>(const_cast<glm::vec4*>(image.rgba.data()));
    fb.insert("R", Imf::Slice(Imf::FLOAT, base + 0, px, px * std::size_t(image.width)));
    fb.insert("G", Imf::Slice(Imf::FLOAT, base + 4, px, px * std::size_t(image.width)));
    fb.insert("B", Imf::Slice(Imf::FLOAT, base + 8, px, px * std::size_t(image.width)));
    fb.insert("A", Imf::Slice(Imf::FLOAT, base + 12, px, px * std::size_t(image.width)));
    fb.insert("Z", Imf::Slice(Imf::FLOAT, reinterpret_cast<char*>(const_cast<float*>(image.depth.data())),
                              sizeof(float), sizeof(float) * std::size_t(image.width)));
    return fb;
}
}  // namespace

void ImageWriter::writeExr(const RenderImage& image, const std::string& path) {
    const std::string tmp = temporaryName(path);
    try {
        Imf::OutputFile file(tmp.c_str(), exrHeader(image, {}));
        file.setFrameBuffer(exrFrameBuffer(image));
        file.writePixels(image.height);
    } catch (const std::exception& e) {
        std::remove(tmp.c_str());
        throw Error(path + ": cannot write EXR (" + e.what() + ")");
    }
    commit(tmp, path);
}

void ImageWriter::writeExrParts(const std::vector<RenderImage>& images, const std::vector<std::string>& names,
                                const std::string& path) {
    if (images.empty() || images.size() != names.size()) throw Error(path + ": a multi-part EXR needs one name per image");
    const std::string tmp = temporaryName(path);
    try {
        std::vector<Imf::Header> headers;
        for (std::size_t i = 0; i < images.size(); ++i) headers.push_back(exrHeader(images[i], names[i]));
        Imf::MultiPartOutputFile file(tmp.c_str(), headers.data(), int(headers.size()));
        for (std::size_t i = 0; i < images.size(); ++i) {
            Imf::OutputPart part(file, int(i));
            part.setFrameBuffer(exrFrameBuffer(images[i]));
            part.writePixels(images[i].height);
        }
    } catch (const std::exception& e) {
        std::remove(tmp.c_str());
        throw Error(path + ": cannot write multi-part EXR (" + e.what() + ")");
    }
    commit(tmp, path);
}

std::vector<std::pair<std::string, std::string>> ImageWriter::libraryVersions() {
    return {{"OpenEXR", OPENEXR_VERSION_STRING}, {"libpng", png_get_libpng_ver(nullptr)}};
}

}  // namespace hvx::core
