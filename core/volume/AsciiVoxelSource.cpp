#include "core/volume/AsciiVoxelSource.h"

#include <sys/stat.h>

#include <algorithm>
#include <bit>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <limits>

#include "core/base/Error.h"

namespace hvx::core {

namespace {
constexpr std::size_t kTextChunk = std::size_t(1) << 20;  // the file's text is read 1 MiB at a time
constexpr std::size_t kLongestToken = 256;                 // no number is written longer

bool isBlank(char c) { return c == ' ' || c == '\t' || c == '\n' || c == '\r' || c == '\v' || c == '\f'; }

template <class T>
void put(unsigned char* out, T v) {
    std::memcpy(out, &v, sizeof v);
}

// The smallest and largest value of an integer element type.
template <class T>
std::pair<long double, long double> limits() {
    return {static_cast<long double>(std::numeric_limits<T>::min()), static_cast<long double>(std::numeric_limits<T>::max())};
}

std::pair<long double, long double> integerRange(FileElement e) {
    switch (e) {
    case FileElement::Int8: return limits<std::int8_t>();
    case FileElement::UInt8: return limits<std::uint8_t>();
    case FileElement::Int16: return limits<std::int16_t>();
    case FileElement::UInt16: return limits<std::uint16_t>();
    case FileElement::Int32: return limits<std::int32_t>();
    case FileElement::UInt32: return limits<std::uint32_t>();
    case FileElement::Int64: return limits<std::int64_t>();
    default: return limits<std::uint64_t>();
    }
}

// A token as a message shows it: at most 32 characters, any but printable ASCII as \xNN.
std::string shown(std::string_view t) {
    std::string out;
    for (const char c : t.substr(0, 32)) {
        if (c >= 0x20 && c < 0x7f) {
            out += c;
        } else {
            char hex[8];
            std::snprintf(hex, sizeof hex, "\\x%02x", unsigned(static_cast<unsigned char>(c)));
            out += hex;
        }
    }
    return t.size() > 32 ? out + "..." : out;
}

std::string integerText(long double v) {
    return v < 0 ? std::to_string(static_cast<long long>(v)) : std::to_string(static_cast<unsigned long long>(v));
}

// Parses `t` as one value of element type `e` into `out` (the element's bytes, in this machine's
// order). Returns an empty string, or why the token is refused (a sentence's end).
std::string parseValue(std::string_view t, FileElement e, unsigned char* out) {
    if (t.size() > 1 && t[0] == '+' && t[1] != '-' && t[1] != '+') t.remove_prefix(1);  // from_chars takes no '+'
    const char* first = t.data();
    const char* last = t.data() + t.size();
    // A number too small for a double ("1e-400"): from_chars reports it as out of range, as it
    // does one too large; a C++ stream and teem read it as zero.
    auto tiny = [t] { return t.find("e-") != std::string_view::npos || t.find("E-") != std::string_view::npos; };
    const bool negative = !t.empty() && t[0] == '-';
    if (e == FileElement::Float32) {  // parsed as a float: rounded once, as a C++ stream reads it
        float f = 0;
        if (const auto r = std::from_chars(first, last, f); r.ec == std::errc() && r.ptr == last) {
            put(out, f);
            return {};
        }
        double d = 0;  // out of a float's range, either way: too small is zero, too large refused
        const auto r = std::from_chars(first, last, d);
        if (r.ec == std::errc::result_out_of_range && r.ptr == last && tiny()) d = negative ? -0.0 : 0.0;
        else if (r.ec != std::errc() || r.ptr != last) return r.ptr == last ? "is beyond what a 32-bit float holds" : "is not a number";
        if (std::abs(d) > double(std::numeric_limits<float>::max())) return "is beyond what a 32-bit float holds";
        put(out, float(d));
        return {};
    }
    if (e == FileElement::Float64) {
        double d = 0;
        const auto r = std::from_chars(first, last, d);
        if (r.ec == std::errc::result_out_of_range && r.ptr == last && tiny()) d = negative ? -0.0 : 0.0;
        else if (r.ec == std::errc::result_out_of_range && r.ptr == last) return "is beyond what a 64-bit float holds";
        else if (r.ec != std::errc() || r.ptr != last) return "is not a number";
        put(out, d);
        return {};
    }
    // An integer: written as one (the usual case), or as a number with a whole value ("3.0", "1e3").
    const long double beyond = (negative ? -1.0L : 1.0L) * std::numeric_limits<long double>::infinity();
    long double v = 0;
    long long s = 0;
    unsigned long long u = 0;
    const auto r = std::from_chars(first, last, s);
    if (r.ec == std::errc() && r.ptr == last) {
        v = static_cast<long double>(s);
    } else if (const auto r2 = std::from_chars(first, last, u); r2.ec == std::errc() && r2.ptr == last) {
        v = static_cast<long double>(u);
    } else if (r.ec == std::errc::result_out_of_range && r.ptr == last) {  // digits beyond 64 bits
        v = beyond;
    } else {
        double d = 0;
        const auto r3 = std::from_chars(first, last, d, std::chars_format::general);
        const bool whole = r3.ptr == last;
        if (r3.ec == std::errc::result_out_of_range && whole && tiny()) return "is not a whole number, as its " + std::string(elementName(e)) + " voxels are";
        if (r3.ec == std::errc::result_out_of_range && whole) d = double(beyond);
        else if (r3.ec != std::errc() || !whole || std::isnan(d)) return "is not a number";
        if (std::isfinite(d) && d != std::floor(d)) return "is not a whole number, as its " + std::string(elementName(e)) + " voxels are";
        // A double holds whole numbers exactly up to 2^53: past that, a value written with a
        // fraction or an exponent may not be the one it rounds to.
        if (std::isfinite(d) && std::abs(d) >= 9007199254740992.0 && (e == FileElement::Int64 || e == FileElement::UInt64))
            return "is too large to be read exactly when written with a fraction or an exponent";
        v = static_cast<long double>(d);  // ±inf, or a whole number: checked against the range below
    }
    const auto [lo, hi] = integerRange(e);
    if (!(v >= lo && v <= hi))
        return "is outside what its " + std::string(elementName(e)) + " voxels hold (" + integerText(lo) + " to " + integerText(hi) + ")";
    switch (e) {
    case FileElement::Int8: put(out, std::int8_t(v)); break;
    case FileElement::UInt8: put(out, std::uint8_t(v)); break;
    case FileElement::Int16: put(out, std::int16_t(v)); break;
    case FileElement::UInt16: put(out, std::uint16_t(v)); break;
    case FileElement::Int32: put(out, std::int32_t(v)); break;
    case FileElement::UInt32: put(out, std::uint32_t(v)); break;
    case FileElement::Int64: put(out, std::int64_t(v)); break;
    default: put(out, std::uint64_t(v)); break;
    }
    return {};
}
}  // namespace

AsciiVoxelSource::AsciiVoxelSource(std::string path, const RawVoxelSource::Options& options)
    : path_(std::move(path)), options_(options), geometry_(options.geometry()) {
    geometry_.validate(path_);
    file_ = std::fopen(path_.c_str(), "rbe");
    if (!file_) throw Error(path_ + ": cannot open (" + std::strerror(errno) + ")");
    struct stat st {};
    if (::fstat(::fileno(file_), &st) != 0 || !S_ISREG(st.st_mode)) {
        std::fclose(file_);
        throw Error(path_ + ": not a regular file");
    }
    std::setvbuf(file_, nullptr, _IONBF, 0);  // read straight into text_
    // Each value takes a digit and a blank at least: a header that promises more values than its
    // file can hold is refused before anything is allocated for them.
    const std::uint64_t size = std::uint64_t(st.st_size);
    const std::uint64_t text = size > options_.headerBytes ? size - options_.headerBytes : 0;
    const std::uint64_t voxels = geometry_.voxelCount();
    if (text < 2 * voxels - 1) {
        std::fclose(file_);
        throw Error(path_ + ": its text data are " + std::to_string(text) + " bytes, too few for the " + std::to_string(voxels) +
                    " voxel values its header gives (each takes a digit and a blank at least)");
    }
    text_.resize(kTextChunk + kLongestToken);
    rewind();
}

AsciiVoxelSource::~AsciiVoxelSource() {
    if (file_) std::fclose(file_);
}

void AsciiVoxelSource::rewind() {
    if (::fseeko(file_, off_t(options_.headerBytes), SEEK_SET) != 0)
        throw Error(path_ + ": cannot seek to its data (" + std::strerror(errno) + ")");
    begin_ = end_ = 0;
    eof_ = false;
    parsed_ = 0;
}

std::string_view AsciiVoxelSource::nextToken() {
    for (;;) {
        while (begin_ < end_ && isBlank(text_[begin_])) ++begin_;
        std::size_t stop = begin_;
        while (stop < end_ && !isBlank(text_[stop])) ++stop;
        if (stop - begin_ > kLongestToken)
            throw Error(path_ + ": " + where(parsed_) + " is more than " + std::to_string(kLongestToken) +
                        " characters long, not a number");
        if (begin_ < end_ && (stop < end_ || eof_)) {  // a whole token
            const std::string_view token(text_.data() + begin_, stop - begin_);
            begin_ = stop;
            return token;
        }
        if (eof_) return {};
        // Keep the token begun (if any) and read on.
        std::memmove(text_.data(), text_.data() + begin_, end_ - begin_);
        end_ -= begin_;
        begin_ = 0;
        const std::size_t got = std::fread(text_.data() + end_, 1, text_.size() - end_, file_);
        if (got == 0 && std::ferror(file_)) throw Error(path_ + ": read failed (" + std::strerror(errno) + ")");
        if (got == 0) eof_ = true;
        end_ += got;
    }
}

std::string AsciiVoxelSource::where(std::uint64_t index) const {
    const std::uint64_t nx = geometry_.dims[0], ny = geometry_.dims[1];
    return "its voxel (" + std::to_string(index % nx) + ", " + std::to_string(index / nx % ny) + ", " +
           std::to_string(index / (nx * ny)) + ") (value number " + std::to_string(index + 1) + ")";
}

void AsciiVoxelSource::parseValues(std::uint64_t n, unsigned char* out) {
    const std::size_t width = elementSize(options_.element);
    for (std::uint64_t i = 0; i < n; ++i, out += width) {
        const std::string_view token = nextToken();
        if (token.empty())
            throw Error(path_ + ": its text data end after " + std::to_string(parsed_) + " of the " +
                        std::to_string(geometry_.voxelCount()) + " voxel values its header gives");
        if (const std::string why = parseValue(token, options_.element, out); !why.empty())
            throw Error(path_ + ": " + where(parsed_) + ", '" + shown(token) + "', " + why);
        ++parsed_;
    }
}

void AsciiVoxelSource::readSlices(std::uint32_t firstSlice, std::uint32_t count, void* dst) {
    const std::uint64_t sliceVoxels = std::uint64_t(geometry_.dims[0]) * geometry_.dims[1];
    const std::uint64_t start = sliceVoxels * firstSlice;
    const std::size_t width = elementSize(options_.element);
    if (start < parsed_) rewind();  // text can only be read forwards
    while (parsed_ < start) {
        const std::uint64_t n = std::min<std::uint64_t>(start - parsed_, std::uint64_t(1) << 20);
        skipped_.resize(std::size_t(n) * width);
        parseValues(n, skipped_.data());
    }
    decodeSlices(options_.element, std::endian::native == std::endian::big, sliceVoxels, firstSlice, count, buffer_, dst,
                 [&](unsigned char* into, std::uint64_t bytes) { parseValues(bytes / width, into); }, path_);
    if (parsed_ == geometry_.voxelCount() && !options_.trailingBytes) {
        if (const std::string_view more = nextToken(); !more.empty())
            throw Error(path_ + ": its text data go on after the " + std::to_string(parsed_) +
                        " voxel values its header gives ('" + shown(more) + "' follows)");
    }
}

}  // namespace hvx::core
