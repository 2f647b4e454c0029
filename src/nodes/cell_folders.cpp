#include "cell_folders.h"

#include <ros/ros.h>

#include <cstdlib>
#include <filesystem>
#include <system_error>

#include "art2part/geometry/mesh.h"

#ifndef ART2PART_SOURCE_DIR
#error "ART2PART_SOURCE_DIR (the package's folder) must be defined by the build"
#endif

namespace art2part {

namespace {

namespace fs = std::filesystem;

const char* const kPartFoldersParam = "/art2part/part_folders";
const char* const kOutputRootParam = "/art2part/output_root";

std::string home() {
  const char* h = std::getenv("HOME");
  return h && *h ? h : "/tmp";
}

// folders.launch's defaults, for a node started without it.
std::vector<std::string> defaultPartFolders() {
  const std::string package = ART2PART_SOURCE_DIR;
  return {package + "/examples", ART2PART_SHARED_PARTS, home() + "/art2part/parts"};
}

std::string defaultOutputRoot() { return home() + "/art2part/plans"; }

std::string joined(const std::vector<std::string>& folders) {
  std::string text;
  for (const std::string& f : folders) text += (text.empty() ? "" : ", ") + f;
  return text;
}

std::vector<std::string> readPartFolders(std::vector<std::string>& problems) {
  std::vector<std::string> folders;
  std::string one;
  if (!ros::param::get(kPartFoldersParam, folders)) {
    if (ros::param::get(kPartFoldersParam, one)) {
      folders = {one};
    } else {
      if (ros::param::has(kPartFoldersParam))
        problems.push_back(std::string(kPartFoldersParam) + " is not a list of folders");
      folders = defaultPartFolders();
      ROS_WARN("%s not set (launch/folders.launch sets it): parts only from %s", kPartFoldersParam,
               joined(folders).c_str());
    }
  }
  std::vector<std::string> absolute;
  for (const std::string& f : folders) {
    if (fs::path(f).is_absolute()) absolute.push_back(f);
    else problems.push_back(std::string(kPartFoldersParam) + ": '" + f + "' is not absolute, ignored");
  }
  if (absolute.empty()) problems.push_back(std::string("no absolute folder in ") + kPartFoldersParam);
  return absolute;
}

std::string readOutputRoot(std::vector<std::string>& problems) {
  std::string root;
  if (!ros::param::get(kOutputRootParam, root)) {
    if (ros::param::has(kOutputRootParam)) problems.push_back(std::string(kOutputRootParam) + " is not a string");
    root = defaultOutputRoot();
    ROS_WARN("%s not set (launch/folders.launch sets it): plans only under %s", kOutputRootParam, root.c_str());
  }
  if (!fs::path(root).is_absolute()) {
    problems.push_back(std::string(kOutputRootParam) + ": '" + root + "' is not absolute: no plan folder is allowed");
    return "";
  }
  return root;
}

}  // namespace

CellFolders readCellFolders(bool create_output_root) {
  CellFolders folders;
  const std::vector<std::string> parts = readPartFolders(folders.problems);
  const std::string output_root = readOutputRoot(folders.problems);
  if (create_output_root && !output_root.empty()) {
    std::error_code error;
    fs::create_directories(resolvedPath(output_root), error);
    if (error) folders.problems.push_back("output_root '" + output_root + "' cannot be made: " + error.message());
  }
  folders.parts = {parts, std::string("part folders (") + kPartFoldersParam + ")"};
  folders.plans = {output_root.empty() ? std::vector<std::string>{} : std::vector<std::string>{output_root},
                   std::string("output folder (") + kOutputRootParam + ")"};
  folders.part_files = folders.parts;
  if (!output_root.empty()) folders.part_files.roots.push_back(output_root);
  folders.part_files.description = std::string("part and output folders (") + kPartFoldersParam + ", " +
                                   kOutputRootParam + ")";
  for (const std::string& p : folders.problems) ROS_ERROR("%s", p.c_str());
  ROS_INFO("part folders: %s; output root: %s", joined(parts).c_str(), output_root.c_str());
  return folders;
}

std::string folderList(const FolderConfinement& confinement) { return joined(confinement.roots); }

std::string confinedField(const FolderConfinement& confinement, const std::string& field,
                          const std::string& requested) {
  const ConfinedPath confined = confinePath(confinement, requested);
  if (!confined.inside) throw InputError(field + " " + confined.refusal);
  return confined.path;
}

std::string outputFolder(const CellFolders& folders, const std::string& field, const std::string& requested) {
  const std::string folder = confinedField(folders.plans, field, requested);
  std::error_code error;
  fs::create_directories(folder, error);
  if (error || !fs::is_directory(folder))
    throw InputError(field + " '" + requested + "' cannot be made: " +
                     (error ? error.message() : std::string("not a directory")));
  return folder;
}

}  // namespace art2part
