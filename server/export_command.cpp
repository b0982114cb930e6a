// `lambert export RESULT.json -o OUT.glb|OUT.ply|OUT.csv` (SPEC §3): a result in an exchange format
// (server/export/export_formats.h), chosen by the output's extension or --format. Exit status: 0
// written, 1 the file could not be written, 2 bad usage or a file that is not a result.
#include <iostream>
#include <memory>
#include <string>

#include "server/cli_common.h"
#include "server/cli_parser.h"
#include "server/export/export_formats.h"

namespace lambert {
namespace {

struct ExportArgs {
  std::string input, output, format, shading = "smooth";
  std::optional<double> white_cd_m2;
};

int run_export(const ExportArgs& args) {
  const std::optional<ExportFormat> format =
      args.format.empty() ? export_format_of_path(args.output) : export_format_named(args.format);
  if (!format) return cli::usage_error("export", "--output: say the format by the extension .glb, .ply or .csv, or with --format");
  std::string text;
  if (!read_text_file(args.input, text)) {
    std::cerr << "lambert export: cannot read " << args.input << "\n";
    return 2;
  }
  ExportOptions options;
  options.shading = args.shading == "flat" ? Shading::Flat : Shading::Smooth;
  options.white_cd_m2 = args.white_cd_m2;
  std::string bytes;
  try {
    bytes = export_result(text, *format, options);
  } catch (const std::invalid_argument& e) {
    std::cerr << "lambert export: " << args.input << ": " << e.what() << " (a result of lambert solve is expected)\n";
    return 2;
  }
  if (!write_text_file("export", args.output, bytes)) return 1;
  std::cout << "wrote " << args.output << " (" << export_format_name(*format) << ", " << bytes.size() << " bytes)\n";
  return 0;
}

}  // namespace

cli::CommandSpec command_export() {
  return {"export", "a result as glTF (.glb) or PLY with colours and values, or its probes as CSV",
          [](cli::Options& o) {
            auto args = std::make_shared<ExportArgs>();
            o.input("RESULT.json", args->input, "a result of lambert solve");
            o.output(args->output, "the file to write: .glb, .ply or .csv").required();
            o.choice("--format", args->format, {"glb", "ply", "csv"}, "the format, when the extension does not say it");
            o.choice("--shading", args->shading, {"smooth", "flat"},
                     "vertex values blended between neighbouring patches, or each patch's own");
            o.positive("--white", args->white_cd_m2,
                       "the luminance in cd/m2 shown as white (default: the result's brightest reflecting patch)");
            o.footer("glTF and PLY: per-vertex colour (sRGB of the luminance), illuminance and luminance\n"
                     "(glTF attributes _ILLUMINANCE_LX, _LUMINANCE_CD_M2), positions in metres.\n"
                     "CSV: one row per probe point: probe, u, v, x, y, z, illuminance_lx, quantity.");
            return [args] { return run_export(*args); };
          }};
}

}  // namespace lambert
