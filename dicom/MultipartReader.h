#pragma once
#include <cstdint>
#include <map>
#include <string>

namespace hvx::dicom {

/// A streaming reader of a multipart/related body (RFC 2046 §5.1, as WADO-RS sends instances):
/// bytes are fed as they arrive and each part's body is handed on in pieces, so that no part is
/// ever held whole. Memory stays bounded by the size of one fed piece plus the boundary.
/// Malformed input (no opening boundary, headers without an end, a part longer than its
/// Content-Length says or longer than the cap, a body that stops before its closing boundary)
/// throws core::Error with a sentence.
///
/// Threading: one reader per body, used from one thread.
class MultipartReader {
public:
    /// What the reader hands on. Header names are lower-case.
    class Sink {
    public:
        virtual ~Sink() = default;
        virtual void beginPart(const std::map<std::string, std::string>& headers) = 0;
        virtual void partData(const char* data, std::size_t size) = 0;
        virtual void endPart() = 0;
    };

    MultipartReader(std::string boundary, Sink& sink, std::uint64_t maxPartBytes);
    /// The boundary parameter of a multipart Content-Type; throws core::Error when the type is
    /// not multipart or names no boundary.
    static std::string boundaryOf(const std::string& contentType);

    void feed(const char* data, std::size_t size);
    /// The body has ended: throws core::Error unless the closing boundary was read.
    void finish() const;
    int partsRead() const { return parts_; }

private:
    enum class State { Preamble, AfterDelimiter, Headers, Body, Done };
    void step();
    bool parseHeaders();
    void emit(std::size_t n);

    std::string delimiter_;  // CRLF "--" boundary
    Sink& sink_;
    std::uint64_t maxPartBytes_;
    std::string buffer_;
    State state_ = State::Preamble;
    std::uint64_t partBytes_ = 0;
    std::int64_t announced_ = -1;  // the part's Content-Length, when it gave one
    int parts_ = 0;
};

}  // namespace hvx::dicom
