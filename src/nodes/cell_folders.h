// The folders a node may read and write, from the global parameters launch/folders.launch sets:
//   /art2part/part_folders  list of absolute folders parts are read from (a single string is one folder)
//   /art2part/output_root   the folder plan folders are written under and read from
// A parameter that is not set takes folders.launch's default (the package's examples/, the shared parts folder beside
// the repository and ~/art2part/parts; ~/art2part/plans), with a warning. Every path a request names goes through
// these before anything is opened (art2part/common/confined_path.h).
#pragma once

#include <string>
#include <vector>

#include "art2part/common/confined_path.h"

namespace art2part {

struct CellFolders {
  FolderConfinement parts;       // part files: load_part, part_server's ~part_file
  FolderConfinement plans;       // output_root alone: output_dir, verify_toolpaths' and run_program's folder
  FolderConfinement part_files;  // parts, then output_root: verify_toolpaths' part_file (a plan's mesh.stl too)
  std::vector<std::string> problems;  // what is wrong with the parameters (relative folders, no output root...)
};

// Reads the parameters (logging what it uses); with `create_output_root`, makes output_root when missing.
CellFolders readCellFolders(bool create_output_root);

// `requested` confined to `confinement` (confinedPathOrThrow), the refusal prefixed with the request's field name:
// "folder '/etc': path is outside the configured output folder (/art2part/output_root)".
std::string confinedField(const FolderConfinement& confinement, const std::string& field,
                          const std::string& requested);

// The roots, comma-separated, for logs and /diagnostics.
std::string folderList(const FolderConfinement& confinement);

// The request's `field` (absolute, or relative to output_root) confined to output_root and made when missing; the
// resolved path. Throws InputError with the refusal, or when the folder cannot be made.
std::string outputFolder(const CellFolders& folders, const std::string& field, const std::string& requested);

}  // namespace art2part
