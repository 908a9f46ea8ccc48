#pragma once
#include <string>

#include "app/cli/CliArgs.h"
#include "core/appearance/TransferFunction.h"
#include "core/volume/VolumeGeometry.h"

namespace hvx::app {

/// `--refraction N | V0:N0,V1:N1,...` of `render` and `lightfield` (thesis §3.2.2): what the
/// transfer function shows refracts with index N (TransferFunction::refractionByOpacity), or
/// the index is N at value V (physical units of `g`), linear between. Sets `tf`'s curve; when
/// `refusal` is not empty (what is asked cannot be drawn with refraction) throws it as
/// core::Error. Nothing happens without the option.
void applyRefractionOption(const CliArgs& args, const core::VolumeGeometry& g, const std::string& refusal,
                           core::TransferFunction& tf);

}  // namespace hvx::app
