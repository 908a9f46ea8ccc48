#pragma once

/// Entry points of holovox-cli's subcommands. Each returns the process exit code and throws
/// core::Error for bad input (main prints it as one line).
namespace hvx::app {
int buildCommand(int argc, char** argv);
int infoCommand(int argc, char** argv);
int phantomCommand(int argc, char** argv);
int demoCommand(int argc, char** argv);
int versionCommand(int argc, char** argv);
int dicomInfoCommand(int argc, char** argv);
int glInfoCommand(int argc, char** argv);
int importCommand(int argc, char** argv);
int studiesCommand(int argc, char** argv);
int pruneCommand(int argc, char** argv);
int removeStudyCommand(int argc, char** argv);
int buildSeriesCommand(int argc, char** argv);
int exportDicomCommand(int argc, char** argv);
int pacsCommand(int argc, char** argv);
int listenCommand(int argc, char** argv);
int renderCommand(int argc, char** argv);
int lightFieldCommand(int argc, char** argv);
int measureCommand(int argc, char** argv);
int labelStatsCommand(int argc, char** argv);
int sliceCommand(int argc, char** argv);
}  // namespace hvx::app
