#include "dicom/Jpeg2000Decoder.h"

#include <openjpeg.h>

#include <algorithm>
#include <cstring>
#include <memory>

#include "core/base/Error.h"

namespace hvx::dicom {

namespace {
struct Memory {
    const std::uint8_t* data;
    std::size_t size;
    std::size_t pos;
};

OPJ_SIZE_T readFn(void* buffer, OPJ_SIZE_T n, void* user) {
    auto* m = static_cast<Memory*>(user);
    if (m->pos >= m->size) return OPJ_SIZE_T(-1);
    const std::size_t k = std::min<std::size_t>(n, m->size - m->pos);
    std::memcpy(buffer, m->data + m->pos, k);
    m->pos += k;
    return k;
}
OPJ_OFF_T skipFn(OPJ_OFF_T n, void* user) {
    auto* m = static_cast<Memory*>(user);
    const auto target = std::clamp<std::int64_t>(std::int64_t(m->pos) + n, 0, std::int64_t(m->size));
    const OPJ_OFF_T moved = OPJ_OFF_T(target - std::int64_t(m->pos));
    m->pos = std::size_t(target);
    return moved;
}
OPJ_BOOL seekFn(OPJ_OFF_T n, void* user) {
    auto* m = static_cast<Memory*>(user);
    if (n < 0 || std::size_t(n) > m->size) return OPJ_FALSE;
    m->pos = std::size_t(n);
    return OPJ_TRUE;
}
void quiet(const char*, void*) {}
}  // namespace

void Jpeg2000Decoder::decode(const std::uint8_t* data, std::size_t size, std::uint32_t width, std::uint32_t height,
                             std::vector<std::int32_t>& out, const std::string& what) {
    if (size < 4) throw core::Error(what + ": JPEG 2000 stream is empty");
    const bool jp2 = size >= 12 && std::memcmp(data + 4, "jP  ", 4) == 0;
    std::unique_ptr<opj_codec_t, void (*)(opj_codec_t*)> codec(opj_create_decompress(jp2 ? OPJ_CODEC_JP2 : OPJ_CODEC_J2K),
                                                               opj_destroy_codec);
    opj_set_error_handler(codec.get(), quiet, nullptr);
    opj_set_warning_handler(codec.get(), quiet, nullptr);
    opj_set_info_handler(codec.get(), quiet, nullptr);
    opj_dparameters_t params;
    opj_set_default_decoder_parameters(&params);
    if (!opj_setup_decoder(codec.get(), &params)) throw core::Error(what + ": cannot set up the JPEG 2000 decoder");
    Memory mem{data, size, 0};
    std::unique_ptr<opj_stream_t, void (*)(opj_stream_t*)> stream(opj_stream_create(1 << 16, OPJ_TRUE),
                                                                  opj_stream_destroy);
    opj_stream_set_user_data(stream.get(), &mem, nullptr);
    opj_stream_set_user_data_length(stream.get(), size);
    opj_stream_set_read_function(stream.get(), readFn);
    opj_stream_set_skip_function(stream.get(), skipFn);
    opj_stream_set_seek_function(stream.get(), seekFn);
    opj_image_t* raw = nullptr;
    if (!opj_read_header(stream.get(), codec.get(), &raw) || !raw)
        throw core::Error(what + ": malformed JPEG 2000 header");
    std::unique_ptr<opj_image_t, void (*)(opj_image_t*)> image(raw, opj_image_destroy);
    if (!opj_decode(codec.get(), stream.get(), image.get()) || !opj_end_decompress(codec.get(), stream.get()))
        throw core::Error(what + ": JPEG 2000 codestream does not decode");
    if (image->numcomps < 1 || !image->comps[0].data)
        throw core::Error(what + ": JPEG 2000 image has no samples");
    if (image->numcomps != 1) throw core::Error(what + ": colour JPEG 2000 images are not volumes");
    const auto& c = image->comps[0];
    if (c.w != width || c.h != height)
        throw core::Error(what + ": JPEG 2000 image is " + std::to_string(c.w) + "x" + std::to_string(c.h) +
                          " but the header says " + std::to_string(width) + "x" + std::to_string(height));
    out.assign(c.data, c.data + std::size_t(width) * height);
}

}  // namespace hvx::dicom
