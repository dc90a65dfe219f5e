// megavox — files other tools read and write: SymVox-family DAGs in and out, OpenVDB / NanoVDB out.
#pragma once
#include <cstdint>
#include <optional>
#include <string>

#include "megavox/device.h"
#include "megavox/encode.h"

namespace mv {

// `megavox export FILE.mvx --format F -o OUT`, F one of
//   symvox-svdag    32-bit SVDAG (.svdag), symvox-ussvdag 32-bit with per-child mirror bits (.ussvdag),
//   symvox-ssvdag   SymVox's compact 16-bit SSVDAG (.ssvdag): each with the header SymVox's viewer reads
//                   (bbox, root side, levels, node count, first-leaf word, word count) and its child order;
//   vdb             an OpenVDB mask grid "voxels" (one active voxel per voxel, world transform kept);
//   nvdb            the same grid as NanoVDB;
//   ply             one vertex per voxel: its centre in model units (double x, y, z) and, when the file has
//                   colours, uchar red, green, blue (binary little endian).
// An .mvx already in the wanted encoding is written as is; otherwise its voxels are decoded and rebuilt.
enum class ExportFormat { symvox_svdag, symvox_ussvdag, symvox_ssvdag, vdb, nvdb, ply };
struct ExportOptions {
  std::string input, output;
  ExportFormat format = ExportFormat::symvox_svdag;
  bool no_clobber = false;  // refuse to replace an existing output (an input is never replaced)
};
struct ExportReport {
  std::string input, output, format;
  uint64_t voxels = 0, bytes = 0;
  bool rebuilt = false;  // re-encoded from the voxels (the .mvx held another encoding)
  bool colours_dropped = false;  // the .mvx has voxel colours, and the format (SymVox) holds geometry only
};
ExportReport export_mvx(Device& dev, const ExportOptions& options);
// The output, resolved and checked as io/output_path.h says (not an input, not a FIFO or device, its folder
// there and writable, ...): the path to write. The call above makes it first; a caller that opens a device
// first (the CLI) makes it before, so a wrong -o costs nothing. Throws mv::Error.
std::string check_output(const ExportOptions& options);

// `megavox import FILE -o OUT.mvx`: the layout (32-bit SVDAG / USSVDAG, 16-bit SSVDAG) is told from the
// content, not the extension, and validated like every reader. Conventions: symvox (child c = 4x + 2y + z,
// root cube centred on the bbox), voxcom (the i3d2025-voxel-transform-dag tools: the same layout written with
// Morton child order x + 2y + 4z and the cube at the bbox's min corner, in voxel units), or auto: voxcom when
// the bbox starts at 0 and the root side is the grid's resolution, else symvox. The voxels are rebuilt into
// `format` (default: the file's own layout).
enum class SymvoxConvention { automatic, symvox, voxcom };
struct ImportOptions {
  std::string input, output;
  SymvoxConvention convention = SymvoxConvention::automatic;
  std::optional<Encoding> encoding;  // svdag, ussvdag or ssvdag; none: the file's layout
  bool no_clobber = false;  // refuse to replace an existing output (an input is never replaced)
};
struct ImportReport {
  std::string input, output, layout, convention, format;
  uint32_t levels = 0;
  uint64_t voxels = 0, nodes_total = 0, bytes = 0, file_nodes = 0;
};
ImportReport import_symvox(Device& dev, const ImportOptions& options);
std::string check_output(const ImportOptions& options);  // as export's

}  // namespace mv
