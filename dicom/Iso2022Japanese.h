#pragma once
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace hvx::dicom {

/// Japanese text as DICOM writes it with code extensions (PS3.5 6.1.2.5 and Annex H):
/// ISO 2022 IR 6 or IR 13 (JIS X 0201 Romaji and half-width Katakana) in its first value, and
/// ISO 2022 IR 87 (JIS X 0208 Kanji) and IR 159 (JIS X 0212) invoked by escape sequences.
/// Debian's DCMTK converts through glibc iconv, which has no name for these sets, and leaves such
/// text as written (escape sequences and 7-bit JIS pairs shown as ASCII garbage). This reads it.
class Iso2022Japanese {
public:
    /// Whether `characterSet` (the values of Specific Character Set, the first possibly empty)
    /// names Japanese code extensions and nothing this reader does not know.
    static bool handles(const std::vector<std::string>& characterSet);
    /// The text in UTF-8, or nothing when it holds an escape sequence or a byte these sets do not
    /// define. At the delimiters where PS3.5 6.1.2.5.3 returns to the first value's set (line
    /// ends, tab, form feed, the value delimiter "\" and, in a person name, "^" and "="), the
    /// reading returns there too; inside a two-byte set such bytes are halves of a character
    /// (the writer returns to the first set before a delimiter, as the standard asks).
    static std::optional<std::string> toUtf8(std::string_view text, const std::vector<std::string>& characterSet,
                                             bool personName);
};

}  // namespace hvx::dicom
