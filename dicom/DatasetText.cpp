#include "dicom/DatasetText.h"

#include <dcmtk/config/osconfig.h>
#include <dcmtk/dcmdata/dcdeftag.h>
#include <dcmtk/dcmdata/dcitem.h>
#include <dcmtk/dcmdata/dcsequen.h>

#include <mutex>
#include <string>
#include <string_view>
#include <vector>

#include "dicom/Iso2022Japanese.h"

namespace hvx::dicom {

namespace {
/// The values of Specific Character Set, the first possibly empty ("\\ISO 2022 IR 87").
std::vector<std::string> characterSetTerms(const std::string& value) {
    std::vector<std::string> terms(1);
    for (char c : value) {
        if (c == '\\') terms.emplace_back();
        else terms.back() += c;
    }
    for (auto& t : terms) {  // the padding of a CS value
        t.erase(0, t.find_first_not_of(' '));
        t.erase(t.find_last_not_of(' ') + 1);
    }
    return terms;
}

/// Text in Japanese code extensions converted to UTF-8 in place, in `item` and its sequences (an
/// item may name its own set); Specific Character Set then says ISO_IR 192. A value that
/// Iso2022Japanese cannot read is left as written, and the set is then left as it was.
void convertJapanese(DcmItem& item, std::vector<std::string> terms) {
    OFString value;
    if (item.findAndGetOFStringArray(DCM_SpecificCharacterSet, value, OFFalse).good())
        terms = characterSetTerms(value.c_str());
    if (!Iso2022Japanese::handles(terms)) return;
    bool whole = true;
    for (unsigned long i = 0; i < item.card(); ++i) {
        DcmElement* e = item.getElement(i);
        const DcmEVR vr = e->ident();
        if (vr == EVR_SQ) {
            auto* sq = static_cast<DcmSequenceOfItems*>(e);
            for (unsigned long k = 0; k < sq->card(); ++k) convertJapanese(*sq->getItem(k), terms);
            continue;
        }
        if (vr != EVR_PN && vr != EVR_SH && vr != EVR_LO && vr != EVR_ST && vr != EVR_LT && vr != EVR_UT && vr != EVR_UC)
            continue;
        OFString raw;
        if (e->getOFStringArray(raw, OFFalse).bad()) continue;
        if (const auto utf8 = Iso2022Japanese::toUtf8(std::string_view(raw.c_str(), raw.length()), terms, vr == EVR_PN))
            e->putString(utf8->c_str(), Uint32(utf8->size()));
        else
            whole = false;
    }
    if (whole) item.putAndInsertString(DCM_SpecificCharacterSet, "ISO_IR 192");
}

}  // namespace

void DatasetText::toUtf8(DcmItem& item) {
    OFString set;
    if (item.findAndGetOFStringArray(DCM_SpecificCharacterSet, set).bad() || set.empty() || set == "ISO_IR 192")
        return;
    // One conversion at a time: each opens and closes iconv (DCMTK's and EUC-JP's here), and
    // glibc loads and unloads its gconv modules with dlopen and dlclose for it. ThreadSanitizer
    // cannot see the dynamic loader's own lock and reported two header-reading threads' frees
    // and allocations in ld.so as a race; the conversions take microseconds.
    static std::mutex conversions;
    const std::lock_guard<std::mutex> lock(conversions);
    if (item.convertToUTF8().bad()) convertJapanese(item, {});
}

}  // namespace hvx::dicom
