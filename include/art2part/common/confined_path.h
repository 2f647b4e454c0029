// Path confinement: a request may name only paths inside configured folders. A path is resolved the way the operating
// system will resolve it when the file is opened (symbolic links followed, `..` applied to what a link points at),
// and is inside a folder when the resolved path is that folder or lies below it, compared element by element (so
// /a/bc is not inside /a/b). A refusal says the same whether or not the file exists, so a caller cannot probe the
// file system with it; an inside path that does not exist is for the opener to report.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

namespace art2part {

// The folders a request may name paths in, and how a refusal names them.
struct FolderConfinement {
  std::vector<std::string> roots;  // absolute folders; a relative request is taken relative to the first
  std::string description;         // what the roots are, for the refusal: "part folders (/art2part/part_folders)"
};

// The outcome of confining one requested path.
struct ConfinedPath {
  bool inside = false;  // the resolved path is a root or lies below one
  std::string path;     // when inside: the resolved path, absolute, no `.`, `..` or links (open this one)
  std::string refusal;  // when not inside: one line naming the request as given, never whether it exists
};

// The refusal for a path outside `confinement`: "'<requested>': path is outside the configured <description>".
std::string outsideRefusal(const FolderConfinement& confinement, const std::string& requested);

// The path the operating system opens for `absolute`: every existing symbolic link replaced by its target (dangling
// ones too), `.` dropped and `..` applied after the links before it are resolved; a missing tail stays as written.
// Components that cannot be examined (no permission, not a folder) are kept as written. Throws InputError for more
// than 40 links (a loop).
std::filesystem::path resolvedPath(const std::filesystem::path& absolute);

// True when `path` is `root` or lies below it, element by element (both already resolved).
bool isInsideFolder(const std::filesystem::path& path, const std::filesystem::path& root);

// Confines `requested` (absolute, or relative to the first absolute root; relative roots are ignored) to the roots.
// An empty request and a confinement with no roots are refused with their own fixed reasons; a NUL character or a
// link loop in the request gets the outside refusal, whatever the path is.
ConfinedPath confinePath(const FolderConfinement& confinement, const std::string& requested);

// confinePath, throwing InputError with the refusal; returns the resolved path.
std::string confinedPathOrThrow(const FolderConfinement& confinement, const std::string& requested);

}  // namespace art2part
