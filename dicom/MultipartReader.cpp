#include "dicom/MultipartReader.h"

#include <algorithm>
#include <cctype>

#include "core/base/Error.h"

namespace hvx::dicom {

namespace {
constexpr std::size_t kMaxHeaderBytes = 16 << 10;
constexpr std::size_t kMaxPreambleBytes = 64 << 10;

std::string lower(std::string s) {
    std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return char(std::tolower(c)); });
    return s;
}
std::string trim(const std::string& s) {
    const auto b = s.find_first_not_of(" \t");
    if (b == std::string::npos) return {};
    return s.substr(b, s.find_last_not_of(" \t") - b + 1);
}
}  // namespace

MultipartReader::MultipartReader(std::string boundary, Sink& sink, std::uint64_t maxPartBytes)
    : delimiter_("\r\n--" + std::move(boundary)), sink_(sink), maxPartBytes_(maxPartBytes) {
    buffer_ = "\r\n";  // the first delimiter may open the body without a CRLF before it
}

std::string MultipartReader::boundaryOf(const std::string& contentType) {
    const std::string t = lower(contentType);
    if (t.rfind("multipart/", 0) != 0)
        throw core::Error("the answer is '" + contentType + "', not a multipart body of DICOM instances");
    const auto at = t.find("boundary=");
    if (at == std::string::npos) throw core::Error("the multipart answer names no boundary ('" + contentType + "')");
    std::string b = contentType.substr(at + 9);
    if (!b.empty() && b[0] == '"') {
        const auto end = b.find('"', 1);
        if (end == std::string::npos) throw core::Error("the multipart answer's boundary is not closed by a quote");
        b = b.substr(1, end - 1);
    } else {
        b = trim(b.substr(0, b.find(';')));
    }
    if (b.empty() || b.size() > 70) throw core::Error("the multipart answer's boundary is empty or too long");
    return b;
}

void MultipartReader::feed(const char* data, std::size_t size) {
    if (state_ == State::Done) return;  // the epilogue is ignored
    buffer_.append(data, size);
    step();
}

void MultipartReader::emit(std::size_t n) {
    if (n == 0) return;
    partBytes_ += n;
    if (partBytes_ > maxPartBytes_)
        throw core::Error("instance " + std::to_string(parts_) + " of the multipart answer is larger than the " +
                          std::to_string(maxPartBytes_ >> 20) + " MiB an instance may be; refused");
    if (announced_ >= 0 && partBytes_ > std::uint64_t(announced_))
        throw core::Error("instance " + std::to_string(parts_) + " of the multipart answer is longer than the " +
                          std::to_string(announced_) + " bytes its Content-Length announced");
    sink_.partData(buffer_.data(), n);
    buffer_.erase(0, n);
}

bool MultipartReader::parseHeaders() {
    // Header lines, each ending in CRLF, then an empty line; a part may have no header at all.
    if (buffer_.size() < 2) return false;
    const auto end = buffer_.compare(0, 2, "\r\n") == 0 ? std::size_t(0) : buffer_.find("\r\n\r\n");
    if (end == std::string::npos) {
        if (buffer_.size() > kMaxHeaderBytes)
            throw core::Error("a part of the multipart answer has headers without an end");
        return false;
    }
    std::map<std::string, std::string> headers;
    std::size_t at = 0;
    while (at < end) {
        std::size_t eol = buffer_.find("\r\n", at);
        if (eol == std::string::npos || eol > end) eol = end;
        const std::string line = buffer_.substr(at, eol - at);
        const auto colon = line.find(':');
        if (colon != std::string::npos) headers[lower(trim(line.substr(0, colon)))] = trim(line.substr(colon + 1));
        at = eol + 2;
    }
    buffer_.erase(0, end == 0 ? 2 : end + 4);
    announced_ = -1;
    if (const auto it = headers.find("content-length"); it != headers.end()) {
        try {
            announced_ = std::stoll(it->second);
        } catch (const std::exception&) {
            throw core::Error("a part of the multipart answer has an unreadable Content-Length '" + it->second + "'");
        }
    }
    partBytes_ = 0;
    ++parts_;
    sink_.beginPart(headers);
    return true;
}

void MultipartReader::step() {
    for (;;) {
        switch (state_) {
            case State::Preamble: {
                const auto at = buffer_.find(delimiter_);
                if (at == std::string::npos) {
                    if (buffer_.size() > kMaxPreambleBytes)
                        throw core::Error("the multipart answer does not begin with its boundary");
                    return;
                }
                buffer_.erase(0, at + delimiter_.size());
                state_ = State::AfterDelimiter;
                break;
            }
            case State::AfterDelimiter: {
                // "--" closes the body; otherwise optional white space and CRLF open a part.
                if (buffer_.size() < 2) return;
                if (buffer_.compare(0, 2, "--") == 0) {
                    state_ = State::Done;
                    buffer_.clear();
                    return;
                }
                const auto eol = buffer_.find("\r\n");
                if (eol == std::string::npos) {
                    if (buffer_.size() > 256) throw core::Error("the multipart answer has a malformed boundary line");
                    return;
                }
                if (!trim(buffer_.substr(0, eol)).empty())
                    throw core::Error("the multipart answer has a malformed boundary line");
                buffer_.erase(0, eol + 2);
                state_ = State::Headers;
                break;
            }
            case State::Headers:
                if (!parseHeaders()) return;
                state_ = State::Body;
                break;
            case State::Body: {
                const auto at = buffer_.find(delimiter_);
                if (at == std::string::npos) {
                    // Keep what could be the start of a delimiter split across two pieces.
                    if (buffer_.size() >= delimiter_.size()) emit(buffer_.size() - (delimiter_.size() - 1));
                    return;
                }
                emit(at);
                if (announced_ >= 0 && partBytes_ != std::uint64_t(announced_))
                    throw core::Error("instance " + std::to_string(parts_) + " of the multipart answer is " +
                                      std::to_string(partBytes_) + " bytes, not the " + std::to_string(announced_) +
                                      " its Content-Length announced");
                buffer_.erase(0, delimiter_.size());
                sink_.endPart();
                state_ = State::AfterDelimiter;
                break;
            }
            case State::Done:
                return;
        }
    }
}

void MultipartReader::finish() const {
    if (state_ == State::Done) return;
    if (state_ == State::Preamble) throw core::Error("the multipart answer holds no boundary: it is not what was asked for");
    throw core::Error("the multipart answer ended before its closing boundary (cut off after " +
                      std::to_string(parts_) + " part(s))");
}

}  // namespace hvx::dicom
