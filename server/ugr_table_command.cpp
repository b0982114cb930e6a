// `lambert ugr-table FILE [--flux LM] [--json] [-o OUT]` (SPEC §3): a photometric file's standard
// UGR table by CIE 190 (solver/ugr_table.h). Exit status: 0 printed, 1 the output could not be
// written, 2 bad usage, a file that does not read, or one without a luminous area.
#include <cctype>
#include <filesystem>
#include <iostream>
#include <memory>
#include <string>

#include "server/cli_common.h"
#include "server/cli_parser.h"
#include "server/ugr_table_codec.h"
#include "solver/photometry/distribution.h"

namespace lambert {
namespace {

struct UgrTableArgs {
  std::string input, output;
  std::optional<double> flux_lm;
  bool json = false;
};

int run_ugr_table(const UgrTableArgs& args) {
  std::string text;
  if (!read_text_file(args.input, text)) {
    std::cerr << "lambert ugr-table: cannot read " << args.input << "\n";
    return 2;
  }
  std::string extension = std::filesystem::path(args.input).extension().string();
  for (char& c : extension) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  const std::string name = std::filesystem::path(args.input).filename().string();
  const PhotometricParse parse = extension == ".ldt" ? parse_ldt(text, name) : parse_ies(text, name);
  if (!parse.ok()) {
    std::cerr << "lambert ugr-table: " << parse.error << "\n";
    return 2;
  }
  const PhotometricDistribution distribution(*parse.data);
  const double integral = distribution.flux();
  if (args.flux_lm && !(integral > 0)) return cli::usage_error("ugr-table", "--flux: the file emits no light to rescale");
  const double scale = args.flux_lm ? *args.flux_lm / integral : 1;
  const std::optional<UgrTable> table = standard_ugr_table(*parse.data, distribution, scale);
  if (!table) {
    std::cerr << "lambert ugr-table: " << name << ": the file gives no luminous area (" << parse.data->opening.description
              << "): L = I / A_p needs one\n";
    return 2;
  }
  const std::string out = args.json ? ugr_table_json(table).dump(1) + "\n" : ugr_table_text(*table);
  if (args.output.empty()) {
    std::cout << out;
    return 0;
  }
  return write_text_file("ugr-table", args.output, out) ? 0 : 1;
}

}  // namespace

cli::CommandSpec command_ugr_table() {
  return {"ugr-table", "a luminaire's standard UGR table (CIE 190) from its IES or EULUMDAT file",
          [](cli::Options& o) {
            auto args = std::make_shared<UgrTableArgs>();
            o.input("FILE", args->input, "an IES LM-63 (.ies) or EULUMDAT (.ldt) file");
            o.output(args->output, "write the table here instead of stdout");
            o.positive("--flux", args->flux_lm, "rescale the file's distribution to this luminous flux in lm");
            o.flag("--json", args->json, "the table as the result's ugr_table JSON");
            o.footer("19 rooms (X across, Y along the line of sight, in H = 2 m) by 5 reflectance sets,\n"
                     "viewed crosswise and endwise, luminaires at S = 0.25 H (docs/METHOD.md).");
            return [args] { return run_ugr_table(*args); };
          }};
}

}  // namespace lambert
