#include "dicom/DicomJson.h"

#include <nlohmann/json.hpp>

#include <cstdio>

#include "core/base/Error.h"

namespace hvx::dicom {

namespace {
using nlohmann::json;

/// The attribute's values joined by backslashes as DICOM strings are, or "" when absent.
/// A DICOM JSON person name (PS3.18 F.2.2) as DIMSE writes it: its alphabetic, ideographic and
/// phonetic groups joined by "=", empty trailing groups left out ("Yamada^Tarou=山田^太郎=...").
std::string personName(const json& name, const char* tag, const std::string& what) {
    const char* const keys[3] = {"Alphabetic", "Ideographic", "Phonetic"};
    std::string groups[3];
    int last = -1;
    for (int i = 0; i < 3; ++i) {
        const auto it = name.find(keys[i]);
        if (it == name.end() || it->is_null()) continue;
        if (!it->is_string())
            throw core::Error(what + ": the " + keys[i] + " group of the person name " + tag + " is not a string");
        groups[i] = it->get<std::string>();
        if (!groups[i].empty()) last = i;
    }
    std::string out;
    for (int i = 0; i <= last; ++i) out += (i ? "=" : "") + groups[i];
    return out;
}

std::string text(const json& object, const char* tag, const std::string& what) {
    const auto it = object.find(tag);
    if (it == object.end()) return {};
    if (!it->is_object()) throw core::Error(what + ": attribute " + tag + " is not a DICOM JSON attribute object");
    const auto values = it->find("Value");
    if (values == it->end()) return {};
    if (!values->is_array()) throw core::Error(what + ": the Value of " + tag + " is not an array");
    std::string out;
    bool first = true;
    for (const auto& v : *values) {
        if (!first) out += '\\';
        first = false;
        if (v.is_string()) out += v.get<std::string>();
        else if (v.is_number_integer()) out += std::to_string(v.get<long long>());
        else if (v.is_number()) out += std::to_string(v.get<double>());
        else if (v.is_object()) out += personName(v, tag, what);
        else if (!v.is_null()) throw core::Error(what + ": a value of " + std::string(tag) + " has an unexpected kind");
    }
    return out;
}

int integer(const json& object, const char* tag, const std::string& what) {
    const std::string t = text(object, tag, what);
    int v = 0;
    return std::sscanf(t.c_str(), "%d", &v) == 1 ? v : 0;
}

json parse(const std::string& body, const std::string& what) {
    try {
        return json::parse(body);
    } catch (const json::exception&) {
        throw core::Error(what + ": the answer is not JSON, so not a DICOM JSON model (it begins '" +
                          body.substr(0, 40) + "')");
    }
}

std::vector<std::string> sequence(const json& object, const char* tag, const std::string& what) {
    std::vector<std::string> out;
    const auto it = object.find(tag);
    if (it == object.end() || !it->is_object()) return out;
    const auto items = it->find("Value");
    if (items == it->end()) return out;
    if (!items->is_array()) throw core::Error(what + ": sequence " + std::string(tag) + " is not an array of items");
    for (const auto& item : *items) {
        if (!item.is_object()) throw core::Error(what + ": an item of " + std::string(tag) + " is not an object");
        std::string uid = text(item, "00081155", what);  // Referenced SOP Instance UID
        const std::string reason = text(item, "00081197", what);  // Failure Reason
        if (!reason.empty()) {
            char code[16];
            std::snprintf(code, sizeof code, "0x%04X", unsigned(std::stoul(reason)) & 0xFFFF);
            uid += std::string(" (reason ") + code + ")";
        }
        out.push_back(uid);
    }
    return out;
}
}  // namespace

std::vector<QueryResult> DicomJson::queryResults(const std::string& body, QueryLevel level, const std::string& what) {
    std::vector<QueryResult> out;
    if (body.find_first_not_of(" \t\r\n") == std::string::npos) return out;
    const json j = parse(body, what);
    if (!j.is_array()) throw core::Error(what + ": the answer is JSON but not a DICOM JSON model (not an array of datasets)");
    for (const auto& o : j) {
        if (!o.is_object()) throw core::Error(what + ": the answer holds something other than DICOM datasets");
        QueryResult r;
        r.level = level;
        r.patientName = text(o, "00100010", what);
        r.patientId = text(o, "00100020", what);
        r.patientBirthDate = text(o, "00100030", what);
        r.studyUid = text(o, "0020000D", what);
        r.studyDate = text(o, "00080020", what);
        r.studyTime = text(o, "00080030", what);
        r.studyDescription = text(o, "00081030", what);
        r.accessionNumber = text(o, "00080050", what);
        r.modalitiesInStudy = text(o, "00080061", what);
        r.seriesUid = text(o, "0020000E", what);
        r.seriesDescription = text(o, "0008103E", what);
        r.modality = text(o, "00080060", what);
        r.seriesNumber = integer(o, "00200011", what);
        r.instanceNumber = integer(o, "00200013", what);
        r.sopInstanceUid = text(o, "00080018", what);
        r.numberOfInstances = integer(o, level == QueryLevel::Study ? "00201208" : "00201209", what);
        out.push_back(std::move(r));
    }
    return out;
}

StowOutcome DicomJson::stowOutcome(const std::string& body, const std::string& what) {
    StowOutcome out;
    if (body.find_first_not_of(" \t\r\n") == std::string::npos) return out;
    json j = parse(body, what);
    if (j.is_array() && j.size() == 1) j = j[0];  // some servers wrap the one dataset in an array
    if (!j.is_object()) throw core::Error(what + ": the STOW-RS answer is not a DICOM JSON dataset");
    try {
        out.stored = sequence(j, "00081199", what);
        out.failed = sequence(j, "00081198", what);
    } catch (const std::logic_error&) {
        throw core::Error(what + ": the STOW-RS answer has an unreadable failure reason");
    }
    return out;
}

}  // namespace hvx::dicom
