// `pvrt export-pov SCENE -o OUT.pov`: the scene in POV-Ray's language, and with
// --povray-command the POV-Ray command line that renders it as `pvrt render` would with
// the same -W, -H, --spp and antialiasing options (the pov sampler's recipe).
#include <cstdio>
#include <filesystem>

#include <fmt/core.h>

#include "cli/commands.h"
#include "core/output_files.h"
#include "core/error.h"
#include "pov_export.h"
#include "render/sampler.h"
#include "scene/xml_loader.h"

namespace pvrt::cli {

namespace {

struct ExportOptions {
  std::string scene, output;
  bool strict = false;
  int aaDepth = 0;
  bool printCommand = false;
  int width = 0, height = 0, spp = 1;
  AdaptiveSettings adaptive;
};

int runExport(const ExportOptions& o) {
  OutputFiles out;  // checked before the scene is read
  out.input(o.scene);
  out.output(o.output, "-o");
  const SceneDesc desc = loadSceneFile(o.scene);
  const PovExport e = exportPov(desc);
  for (const std::string& w : e.warnings) std::fprintf(stderr, "%s\n", w.c_str());
  if (o.strict && !e.warnings.empty())
    throw Error(ExitCode::SceneError, e.warnings.front() + " (--strict)");
  std::string command;
  if (o.printCommand) {  // checked like `pvrt render` checks them, before anything is written
    const PixelSampler sampler(SamplerSettings{SamplerKind::Pov, o.spp, 0, o.adaptive});
    const int w = o.width > 0 ? o.width : (desc.image ? desc.image->width : 320);
    const int h = o.height > 0 ? o.height : (desc.image ? desc.image->height : 240);
    const std::filesystem::path pov(o.output);
    std::filesystem::path png = pov.filename();
    png.replace_extension(".png");
    command = povCommandLine(pov.filename().string(), png.string(), w, h, o.spp > 1 ? sampler.depth() : 0, o.adaptive);
  }
  out.stageBytes(o.output, withRecipe(e.sdl, desc, PovRecipe{o.aaDepth, o.output == "-" ? "scene.pov" : o.output}));
  out.commit();
  if (o.printCommand) fmt::print("{}\n", command);
  return 0;
}

}  // namespace

Command addExportCommand(CLI::App& app) {
  auto o = std::make_shared<ExportOptions>();
  CLI::App* c = app.add_subcommand("export-pov", "Export an XML scene to POV-Ray 3.7 scene language");
  c->add_option("scene", o->scene, "Scene file (XML)")->required();
  c->add_option("-o,--output", o->output, "POV-Ray file to write")->required();
  c->add_option("--aa-depth", o->aaDepth,
                 "The header's command line samples as pvrt's --spp n*n: +A0.0 +AM1 +Rn -J (default: -A, --spp 1)")
      ->check(CLI::Range(1, 9));
  c->add_flag("--strict", o->strict, "Treat anything that cannot be exported as an error");
  CLI::Option* printCommand =
      c->add_flag("--povray-command", o->printCommand,
                  "Print the POV-Ray command line that renders the export (in its folder) as `pvrt render` would "
                  "with these options (which only it takes; the file's own header follows --aa-depth):");
  // Without --povray-command these would change nothing, the header saying -A or --aa-depth's
  // +Rn whatever they ask: refused rather than ignored.
  c->add_option("-W,--width", o->width, "Image width (default: the scene's <image>, else 320)")
      ->check(CLI::Range(1, 65536))
      ->needs(printCommand);
  c->add_option("-H,--height", o->height, "Image height (default: the scene's <image>, else 240)")
      ->check(CLI::Range(1, 65536))
      ->needs(printCommand);
  c->add_option("--spp", o->spp, "Samples per pixel of the pov sampler, n*n for POV-Ray's +Rn (1: -A)")
      ->check(CLI::Range(1, 1 << 16))
      ->needs(printCommand);
  c->add_option("--aa-threshold", o->adaptive.threshold, "POV-Ray's +A t")->needs(printCommand);
  c->add_option("--aa-method", o->adaptive.method, "POV-Ray's +AM")->needs(printCommand);
  c->add_option("--aa-block", o->adaptive.blockSize, "POV-Ray's +BS")->needs(printCommand);
  return [o] { return runExport(*o); };
}

}  // namespace pvrt::cli
