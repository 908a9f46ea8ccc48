#include "ui/TransferFunctionFiles.h"

#include <QFile>
#include <QJsonArray>
#include <QJsonDocument>
#include <QJsonObject>
#include <QSaveFile>
#include <QStringList>
#include <QXmlStreamReader>

#include <algorithm>
#include <cmath>

#include <glm/common.hpp>

#include "core/base/Error.h"

namespace hvx::ui {

namespace {
[[noreturn]] void fail(const QString& path, const QString& why) {
    throw core::Error((path + QStringLiteral(": ") + why).toStdString());
}

QByteArray readAll(const QString& path, qint64 limit = 64 << 20) {
    QFile f(path);
    if (!f.open(QIODevice::ReadOnly)) fail(path, QObject::tr("cannot be opened (%1)").arg(f.errorString()));
    if (f.size() > limit) fail(path, QObject::tr("is too large for a transfer function file"));
    return f.readAll();
}

// Slicer attribute "N v0 v1 ...": N numbers follow.
std::vector<double> numbers(const QString& path, const QString& name, const QString& text) {
    const QStringList parts = text.split(QLatin1Char(' '), Qt::SkipEmptyParts);
    if (parts.isEmpty()) fail(path, QObject::tr("attribute %1 is empty").arg(name));
    bool ok = false;
    const int n = parts[0].toInt(&ok);
    if (!ok || n < 0 || n != parts.size() - 1)
        fail(path, QObject::tr("attribute %1 announces %2 numbers but holds %3").arg(name, parts[0]).arg(parts.size() - 1));
    std::vector<double> out;
    for (int i = 1; i < parts.size(); ++i) {
        const double v = parts[i].toDouble(&ok);
        if (!ok || !std::isfinite(v)) fail(path, QObject::tr("attribute %1 holds '%2', not a number").arg(name, parts[i]));
        out.push_back(v);
    }
    return out;
}
}  // namespace

core::TransferFunctionSpec TransferFunctionFiles::toStored(core::TransferFunctionSpec s, double slope, double intercept) {
    for (auto& p : s.opacity) p.value = (p.value - intercept) / slope;
    for (auto& c : s.colours) c.value = (c.value - intercept) / slope;
    for (auto& g : s.gradientOpacity) g.magnitude /= std::abs(slope);  // per mm, in stored units
    for (auto& r : s.refraction) r.value = (r.value - intercept) / slope;
    return s;
}

core::TransferFunctionSpec TransferFunctionFiles::toPhysical(core::TransferFunctionSpec s, double slope,
                                                             double intercept) {
    for (auto& p : s.opacity) p.value = p.value * slope + intercept;
    for (auto& c : s.colours) c.value = c.value * slope + intercept;
    for (auto& g : s.gradientOpacity) g.magnitude *= std::abs(slope);
    for (auto& r : s.refraction) r.value = r.value * slope + intercept;
    return s;
}

void TransferFunctionFiles::save(const core::TransferFunctionSpec& physical, const QString& path) {
    QJsonArray opacity, colours;
    for (const auto& p : physical.opacity) opacity.append(QJsonArray{p.value, p.alpha});
    for (const auto& c : physical.colours) colours.append(QJsonArray{c.value, c.rgb.r, c.rgb.g, c.rgb.b});
    QJsonObject root{{"format", "holovox-transfer-function"}, {"version", 1}, {"units", "physical"},
                     {"opacity", opacity}, {"colours", colours}};
    if (!physical.gradientOpacity.empty()) {  // [|∇f| per mm, scale]
        QJsonArray gradient;
        for (const auto& g : physical.gradientOpacity) gradient.append(QJsonArray{g.magnitude, g.scale});
        root.insert("gradientOpacity", gradient);
    }
    if (!physical.refraction.empty()) {  // [value, refraction index]
        QJsonArray refraction;
        for (const auto& r : physical.refraction) refraction.append(QJsonArray{r.value, r.index});
        root.insert("refraction", refraction);
    }
    QSaveFile f(path);  // written under a temporary name, renamed on commit
    if (!f.open(QIODevice::WriteOnly)) fail(path, QObject::tr("cannot be written (%1)").arg(f.errorString()));
    f.write(QJsonDocument(root).toJson());
    if (!f.commit()) fail(path, QObject::tr("cannot be written (%1)").arg(f.errorString()));
}

core::TransferFunctionSpec TransferFunctionFiles::load(const QString& path) {
    QJsonParseError err{};
    const auto doc = QJsonDocument::fromJson(readAll(path), &err);
    if (doc.isNull()) fail(path, QObject::tr("is not valid JSON (%1 at byte %2)").arg(err.errorString()).arg(err.offset));
    const auto root = doc.object();
    if (root.value("format").toString() != "holovox-transfer-function")
        fail(path, QObject::tr("is not a Holovox transfer function (no \"format\": \"holovox-transfer-function\")"));
    if (root.value("version").toInt() != 1) fail(path, QObject::tr("has an unsupported version"));
    core::TransferFunctionSpec s;
    for (const auto& v : root.value("opacity").toArray()) {
        const auto a = v.toArray();
        if (a.size() != 2 || !a[0].isDouble() || !a[1].isDouble()) fail(path, QObject::tr("an opacity point is not [value, opacity]"));
        s.opacity.push_back({a[0].toDouble(), a[1].toDouble()});
    }
    for (const auto& v : root.value("colours").toArray()) {
        const auto a = v.toArray();
        if (a.size() != 4) fail(path, QObject::tr("a colour stop is not [value, r, g, b]"));
        for (const auto& x : a)
            if (!x.isDouble()) fail(path, QObject::tr("a colour stop holds something other than numbers"));
        s.colours.push_back({a[0].toDouble(), {a[1].toDouble(), a[2].toDouble(), a[3].toDouble()}});
    }
    for (const auto& v : root.value("gradientOpacity").toArray()) {
        const auto a = v.toArray();
        if (a.size() != 2 || !a[0].isDouble() || !a[1].isDouble())
            fail(path, QObject::tr("a gradient opacity point is not [gradient per mm, scale]"));
        s.gradientOpacity.push_back({a[0].toDouble(), a[1].toDouble()});
    }
    for (const auto& v : root.value("refraction").toArray()) {
        const auto a = v.toArray();
        if (a.size() != 2 || !a[0].isDouble() || !a[1].isDouble())
            fail(path, QObject::tr("a refraction point is not [value, refraction index]"));
        s.refraction.push_back({a[0].toDouble(), a[1].toDouble()});
    }
    try {
        s.normalise();
        core::TransferFunction check({{0, glm::dvec4(0.0)}}, 0, 1);  // checks the curves
        check.setGradientOpacity(s.gradientOpacity);
        check.setRefraction(s.refraction);
    } catch (const core::Error& e) {
        fail(path, QString::fromStdString(e.what()));
    }
    return s;
}

std::vector<std::pair<QString, core::TransferFunctionSpec>> TransferFunctionFiles::readSlicerPresets(const QString& path) {
    QXmlStreamReader xml(readAll(path));
    std::vector<std::pair<QString, core::TransferFunctionSpec>> out;
    while (!xml.atEnd()) {
        if (xml.readNext() != QXmlStreamReader::StartElement || xml.name() != QLatin1String("VolumeProperty")) continue;
        const auto attrs = xml.attributes();
        const QString name = attrs.value("name").toString();
        const auto opacity = numbers(path, "scalarOpacity of " + name, attrs.value("scalarOpacity").toString());
        const auto colours = numbers(path, "colorTransfer of " + name, attrs.value("colorTransfer").toString());
        if (opacity.size() % 2 || colours.size() % 4)
            fail(path, QObject::tr("preset %1: scalarOpacity needs pairs and colorTransfer quadruples").arg(name));
        core::TransferFunctionSpec s;
        for (std::size_t i = 0; i < opacity.size(); i += 2) s.opacity.push_back({opacity[i], std::clamp(opacity[i + 1], 0.0, 1.0)});
        // gradientOpacity="N g0 s0 g1 s1 ...": |∇f| (physical units per mm) and its opacity scale.
        const auto gradient = attrs.hasAttribute("gradientOpacity")
                                  ? numbers(path, "gradientOpacity of " + name, attrs.value("gradientOpacity").toString())
                                  : std::vector<double>{};
        if (gradient.size() % 2) fail(path, QObject::tr("preset %1: gradientOpacity needs pairs").arg(name));
        for (std::size_t i = 0; i < gradient.size(); i += 2)
            s.gradientOpacity.push_back({std::max(0.0, gradient[i]), std::clamp(gradient[i + 1], 0.0, 1.0)});
        for (std::size_t i = 0; i < colours.size(); i += 4)
            s.colours.push_back({colours[i], glm::clamp(glm::dvec3(colours[i + 1], colours[i + 2], colours[i + 3]), 0.0, 1.0)});
        try {
            s.normalise();
        } catch (const core::Error& e) {
            fail(path, QObject::tr("preset %1: %2").arg(name, QString::fromStdString(e.what())));
        }
        out.emplace_back(name, s);
    }
    if (xml.hasError())
        fail(path, QObject::tr("is not valid XML (%1, line %2)").arg(xml.errorString()).arg(xml.lineNumber()));
    if (out.empty()) fail(path, QObject::tr("holds no VolumeProperty preset"));
    return out;
}

core::TransferFunctionSpec TransferFunctionFiles::readParaView(const QString& path, double lo, double hi,
                                                               const core::TransferFunctionSpec& current) {
    QJsonParseError err{};
    const auto doc = QJsonDocument::fromJson(readAll(path), &err);
    if (doc.isNull()) fail(path, QObject::tr("is not valid JSON (%1 at byte %2)").arg(err.errorString()).arg(err.offset));
    const QJsonObject map = doc.isArray() ? doc.array().first().toObject() : doc.object();
    const auto rgb = map.value("RGBPoints").toArray();
    if (rgb.isEmpty() || rgb.size() % 4) fail(path, QObject::tr("has no RGBPoints list of x, r, g, b quadruples"));
    std::vector<double> v;
    for (const auto& x : rgb) {
        if (!x.isDouble()) fail(path, QObject::tr("RGBPoints holds something other than numbers"));
        v.push_back(x.toDouble());
    }
    double x0 = v[0], x1 = v[0];
    for (std::size_t i = 0; i < v.size(); i += 4) x0 = std::min(x0, v[i]), x1 = std::max(x1, v[i]);
    auto place = [&](double x) { return x1 > x0 ? lo + (x - x0) / (x1 - x0) * (hi - lo) : lo; };
    core::TransferFunctionSpec s;
    s.opacity = current.opacity;
    for (std::size_t i = 0; i < v.size(); i += 4)
        s.colours.push_back({place(v[i]), glm::clamp(glm::dvec3(v[i + 1], v[i + 2], v[i + 3]), 0.0, 1.0)});
    const auto points = map.value("Points").toArray();  // x, opacity, midpoint, sharpness
    if (!points.isEmpty()) {
        if (points.size() % 4) fail(path, QObject::tr("Points is not a list of x, opacity, midpoint, sharpness"));
        s.opacity.clear();
        for (int i = 0; i < points.size(); i += 4)
            s.opacity.push_back({place(points[i].toDouble()), std::clamp(points[i + 1].toDouble(), 0.0, 1.0)});
    }
    try {
        s.normalise();
    } catch (const core::Error& e) {
        fail(path, QString::fromStdString(e.what()));
    }
    return s;
}

}  // namespace hvx::ui
