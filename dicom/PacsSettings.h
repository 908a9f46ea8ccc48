#pragma once
#include <string>
#include <vector>

#include "dicom/PacsNode.h"

namespace hvx::dicom {

/// The PACS configuration: the local node and the remote nodes, kept in a JSON settings file
/// (`$HOLOVOX_PACS_CONFIG`, else `$XDG_CONFIG_HOME/holovox/pacs.json`).
struct PacsSettings {
    LocalNode local;
    std::vector<PacsNode> nodes;
    std::string defaultNode;

    /// Loads the file; a missing file gives defaults. Throws core::Error naming the file and the
    /// bad field for malformed content (bad JSON, AE titles over 16 characters, ports 0).
    static PacsSettings load(const std::string& path);
    /// Writes the file atomically.
    void save(const std::string& path) const;
    static std::string defaultPath();
    /// The node called `name` (or the default node when empty); throws core::Error otherwise.
    const PacsNode& node(const std::string& name) const;
    /// Replaces or adds a node by name.
    void upsert(const PacsNode& node);
};

}  // namespace hvx::dicom
