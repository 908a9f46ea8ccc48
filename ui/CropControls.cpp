#include "ui/CropControls.h"

#include <QCheckBox>
#include <QDoubleSpinBox>
#include <QGridLayout>
#include <QLabel>
#include <QPushButton>

#include <cmath>

#include "core/base/Error.h"

namespace hvx::ui {

namespace {
/// The LPS letter an axis runs towards (its largest component).
QString towards(const glm::dvec3& d) {
    int a = 0;
    for (int i = 1; i < 3; ++i)
        if (std::abs(d[i]) > std::abs(d[a])) a = i;
    static const char* plus[3] = {"L", "P", "S"};
    static const char* minus[3] = {"R", "A", "I"};
    return QString::fromLatin1(d[a] >= 0 ? plus[a] : minus[a]);
}
}  // namespace

CropControls::CropControls(QWidget* parent)
    : QWidget(parent), enabled_(new QCheckBox(tr("Crop to the box"), this)), problem_(new QLabel(this)) {
    enabled_->setObjectName("cropEnabled");
    enabled_->setToolTip(tr("What the box removes is neither drawn nor loaded"));
    problem_->setObjectName("cropProblem");
    problem_->setWordWrap(true);
    problem_->setStyleSheet("color: #c33");
    auto* grid = new QGridLayout(this);
    grid->addWidget(enabled_, 0, 0, 1, 3);
    grid->addWidget(new QLabel(tr("from (mm)"), this), 1, 1);
    grid->addWidget(new QLabel(tr("to (mm)"), this), 1, 2);
    for (int a = 0; a < 3; ++a) {
        axes_[std::size_t(a)] = new QLabel(this);
        grid->addWidget(axes_[std::size_t(a)], 2 + a, 0);
        for (int side = 0; side < 2; ++side) {
            auto* s = new QDoubleSpinBox(this);
            s->setObjectName(QStringLiteral("crop%1%2").arg(QChar('i' + a)).arg(side ? "High" : "Low"));
            s->setDecimals(1);
            s->setKeyboardTracking(false);
            faces_[std::size_t(side * 3 + a)] = s;
            grid->addWidget(s, 2 + a, 1 + side);
            connect(s, &QDoubleSpinBox::valueChanged, this, &CropControls::apply);
        }
    }
    auto* reset = new QPushButton(tr("Whole volume"), this);
    reset->setObjectName("cropReset");
    reset->setToolTip(tr("Reset the box to the whole volume"));
    grid->addWidget(reset, 5, 0, 1, 3);
    grid->addWidget(problem_, 6, 0, 1, 3);
    connect(enabled_, &QCheckBox::toggled, this, &CropControls::apply);
    connect(reset, &QPushButton::clicked, this, [this] { setBox({}); });
    setVolume(dims_, spacing_, glm::dmat3(1.0));
}

void CropControls::setVolume(const std::array<std::uint32_t, 3>& dims, const glm::dvec3& spacing,
                             const glm::dmat3& direction) {
    dims_ = dims;
    spacing_ = spacing;
    for (int a = 0; a < 3; ++a) {
        const glm::dvec3 d = direction[a];
        axes_[std::size_t(a)]->setText(QStringLiteral("%1 (%2\u2192%3)").arg(QChar('i' + a)).arg(towards(-d), towards(d)));
        const double length = double(dims[std::size_t(a)]) * spacing[a];
        // Two significant digits of the voxel at least (0.1 mm of a 0.05 mm voxel is two voxels).
        const int decimals = std::clamp(int(std::ceil(-std::log10(spacing[a]))) + 1, 1, 4);
        for (int side = 0; side < 2; ++side) {
            const QSignalBlocker block(faces_[std::size_t(side * 3 + a)]);
            faces_[std::size_t(side * 3 + a)]->setDecimals(decimals);
            faces_[std::size_t(side * 3 + a)]->setRange(0.0, length);
            faces_[std::size_t(side * 3 + a)]->setSingleStep(spacing[a]);
        }
    }
    setBox({});
}

void CropControls::setBox(const core::CropBox& box) {
    const auto mm = box.millimetres(dims_, spacing_);
    {
        const QSignalBlocker block(enabled_);
        enabled_->setChecked(!box.whole());
        for (int a = 0; a < 3; ++a) {
            const QSignalBlocker lo(faces_[std::size_t(a)]), hi(faces_[std::size_t(3 + a)]);
            faces_[std::size_t(a)]->setValue(mm[0][a]);
            faces_[std::size_t(3 + a)]->setValue(mm[1][a]);
        }
    }
    // The box itself, not its faces read back from the fields, which round to their decimals.
    box_ = box;
    problem_->clear();
    emit changed();
}

void CropControls::apply() {
    glm::dvec3 lo, hi;
    for (int a = 0; a < 3; ++a) {
        lo[a] = faces_[std::size_t(a)]->value();
        hi[a] = faces_[std::size_t(3 + a)]->value();
    }
    try {
        box_ = core::CropBox::fromMillimetres(lo, hi, dims_, spacing_);
        problem_->clear();
    } catch (const core::Error& e) {  // keep the last good box, say why this one is not used
        problem_->setText(QString::fromStdString(e.what()));
    }
    emit changed();
}

core::CropBox CropControls::box() const { return enabled_->isChecked() ? box_ : core::CropBox{}; }

bool CropControls::isOn() const { return enabled_->isChecked(); }

QString CropControls::problem() const { return problem_->text(); }

}  // namespace hvx::ui
