// Japanese code extensions read to UTF-8 (the whole files are compared with pydicom in
// PydicomSeries.PydicomsCharacterSetFilesAreReadAsPydicomReadsThem); here what is broken or
// hostile: nothing is guessed, the text is left to the caller as written.
#include <gtest/gtest.h>

#include "dicom/Iso2022Japanese.h"

using hvx::dicom::Iso2022Japanese;

namespace {
const std::vector<std::string> kIr87{"", "ISO 2022 IR 87"};
const std::vector<std::string> kIr13{"ISO 2022 IR 13", "ISO 2022 IR 87"};
const std::vector<std::string> kIr13Only{"ISO 2022 IR 13"};
const std::vector<std::string> kIr159{"", "ISO 2022 IR 159"};
}  // namespace

TEST(Iso2022Japanese, KanjiKatakanaAndTheReturnToTheFirstSetAtEachDelimiter) {
    // 山田 (JIS 0x3B33 0x4544) then, after "^" without an escape back, ASCII again.
    EXPECT_EQ(Iso2022Japanese::toUtf8("\x1b$B;3ED\x1b(B^Tarou", kIr87, true).value(), "\u5c71\u7530^Tarou");
    // Half-width Katakana ﾔﾏﾀﾞ in G1 of IR 13, read at the start and after "=".
    EXPECT_EQ(Iso2022Japanese::toUtf8("\xd4\xcf\xc0\xde=\xd4", kIr13, true).value(), "\uff94\uff8f\uff80\uff9e=\uff94");
    // In a text that is not a person name, "^" is a character of the Kanji run it stands in.
    EXPECT_TRUE(Iso2022Japanese::toUtf8("\x1b$B$^\x1b(B", kIr87, false).has_value());
    EXPECT_EQ(Iso2022Japanese::toUtf8("plain", kIr87, false).value(), "plain");
}

TEST(Iso2022Japanese, BrokenOrForeignTextIsNotGuessed) {
    EXPECT_FALSE(Iso2022Japanese::toUtf8("\x1b$B;", kIr87, true));         // half a Kanji
    EXPECT_FALSE(Iso2022Japanese::toUtf8("\x1b$B;\x01", kIr87, true));     // a control byte inside one
    EXPECT_FALSE(Iso2022Japanese::toUtf8("\x1b$)C\xb1\xe8", kIr87, true)); // Korean, not declared
    EXPECT_FALSE(Iso2022Japanese::toUtf8("\x1b", kIr87, true));            // an escape cut short
    EXPECT_FALSE(Iso2022Japanese::toUtf8("\xd4", kIr87, true));            // Katakana without IR 13
    EXPECT_FALSE(Iso2022Japanese::toUtf8("\x1b)I\xb6", kIr87, true));      // ... even when designated
    EXPECT_FALSE(Iso2022Japanese::toUtf8("\x1b$(D0!", kIr87, true));       // JIS X 0212 without IR 159
    EXPECT_FALSE(Iso2022Japanese::toUtf8("\x1b$B;3", kIr13Only, true));    // Kanji without IR 87
    EXPECT_TRUE(Iso2022Japanese::toUtf8("\x1b$(D0!", kIr159, true).has_value());
    EXPECT_FALSE(Iso2022Japanese::toUtf8("\xe9", kIr13, true));            // beyond the Katakana
    EXPECT_FALSE(Iso2022Japanese::toUtf8("\x1b$B\x29\x21", kIr87, true));  // row 9: no characters
    EXPECT_FALSE(Iso2022Japanese::handles({"ISO_IR 100"}));
    EXPECT_FALSE(Iso2022Japanese::handles({"", "ISO 2022 IR 87", "ISO 2022 IR 149"}));
    EXPECT_FALSE(Iso2022Japanese::handles({"", "ISO 2022 IR 6"}));  // nothing Japanese in it
    EXPECT_TRUE(Iso2022Japanese::handles(kIr13));
}
