#pragma once

class DcmItem;  // private to dicom/: only .cpp files of this module use this helper

namespace hvx::dicom {

/// The text of a dataset (a file's header, a C-FIND answer) in UTF-8, whatever its Specific
/// Character Set says it was written in (PS3.5 6.1): through DCMTK's conversion (glibc iconv:
/// ISO_IR 100..166, Korean, GB18030, ...), and Japanese code extensions (ISO 2022 IR 13, 87,
/// 159), which iconv has no name for, through Iso2022Japanese. A set neither reads is left as
/// written.
class DatasetText {
public:
    /// Converts `item` in place; its Specific Character Set then says ISO_IR 192.
    static void toUtf8(DcmItem& item);
};

}  // namespace hvx::dicom
