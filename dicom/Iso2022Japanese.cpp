#include "dicom/Iso2022Japanese.h"

#include <iconv.h>

#include <algorithm>

namespace hvx::dicom {

namespace {
const char* const kKnown[] = {"", "ISO 2022 IR 6", "ISO 2022 IR 13", "ISO 2022 IR 87", "ISO 2022 IR 159"};

/// EUC-JP, the one encoding of glibc iconv that holds JIS X 0201 Katakana, JIS X 0208 and
/// JIS X 0212 side by side: ASCII as it is, Katakana after 0x8E, JIS X 0208 pairs with their
/// high bits set, JIS X 0212 pairs after 0x8F.
std::optional<std::string> eucJpToUtf8(const std::string& euc) {
    iconv_t cd = ::iconv_open("UTF-8", "EUC-JP");
    if (cd == iconv_t(-1)) return std::nullopt;
    std::string out(euc.size() * 3 + 4, '\0');
    char* in = const_cast<char*>(euc.data());
    std::size_t inLeft = euc.size();
    char* at = out.data();
    std::size_t outLeft = out.size();
    const std::size_t r = ::iconv(cd, &in, &inLeft, &at, &outLeft);
    ::iconv_close(cd);
    if (r == std::size_t(-1) || inLeft != 0) return std::nullopt;
    out.resize(out.size() - outLeft);
    return out;
}
}  // namespace

bool Iso2022Japanese::handles(const std::vector<std::string>& characterSet) {
    bool japanese = false;
    for (const auto& term : characterSet) {
        if (std::find(std::begin(kKnown), std::end(kKnown), term) == std::end(kKnown)) return false;
        japanese = japanese || term == "ISO 2022 IR 13" || term == "ISO 2022 IR 87" || term == "ISO 2022 IR 159";
    }
    return japanese;
}

std::optional<std::string> Iso2022Japanese::toUtf8(std::string_view text, const std::vector<std::string>& characterSet,
                                                   bool personName) {
    if (!handles(characterSet)) return std::nullopt;
    // The first value's set is in force at the start and after each delimiter: G0 ASCII (or
    // JIS X 0201 Romaji, read as ASCII: its yen sign and overline sit where ASCII has the
    // backslash and tilde, and the backslash is the value delimiter), and with
    // IR 13 the half-width Katakana in G1 (bytes 0xA1..0xDF).
    const bool katakanaFirst = !characterSet.empty() && characterSet.front() == "ISO 2022 IR 13";
    auto declared = [&](const char* term) {
        return std::find(characterSet.begin(), characterSet.end(), term) != characterSet.end();
    };
    const bool ir13 = declared("ISO 2022 IR 13"), ir87 = declared("ISO 2022 IR 87"), ir159 = declared("ISO 2022 IR 159");
    enum class G0 { Ascii, Jis0208, Jis0212 } g0 = G0::Ascii;
    bool katakana = katakanaFirst;
    std::string euc;
    for (std::size_t i = 0; i < text.size();) {
        const unsigned char c = static_cast<unsigned char>(text[i]);
        if (c == 0x1B) {  // ESC: designate a set
            const std::string_view rest = text.substr(i + 1);
            auto starts = [&](std::string_view seq) { return rest.substr(0, seq.size()) == seq; };
            // Only the sets Specific Character Set names: ASCII, and with IR 13 its Romaji and
            // Katakana, with IR 87 JIS X 0208, with IR 159 JIS X 0212.
            if (starts("(B") || (ir13 && starts("(J"))) g0 = G0::Ascii, i += 3;
            else if (ir87 && starts("$B")) g0 = G0::Jis0208, i += 3;
            else if (ir159 && starts("$(D")) g0 = G0::Jis0212, i += 4;
            else if (ir13 && starts(")I")) katakana = true, i += 3;
            else return std::nullopt;  // a set not named in Specific Character Set
            continue;
        }
        if (g0 != G0::Ascii && c >= 0x21 && c <= 0x7E) {  // a two-byte character
            if (i + 1 >= text.size()) return std::nullopt;
            const unsigned char d = static_cast<unsigned char>(text[i + 1]);
            if (d < 0x21 || d > 0x7E) return std::nullopt;
            if (g0 == G0::Jis0212) euc += char(0x8F);
            euc += char(c | 0x80);
            euc += char(d | 0x80);
            i += 2;
            continue;
        }
        const bool delimiter = c == '\r' || c == '\n' || c == '\f' || c == '\t' || c == '\\' ||
                               (personName && (c == '^' || c == '='));
        if (delimiter) {
            g0 = G0::Ascii;
            katakana = katakanaFirst;
        }
        if (c < 0x80) {
            euc += char(c);
        } else if (katakana && c >= 0xA1 && c <= 0xDF) {
            euc += char(0x8E);
            euc += char(c);
        } else {
            return std::nullopt;
        }
        ++i;
    }
    return eucJpToUtf8(euc);
}

}  // namespace hvx::dicom
