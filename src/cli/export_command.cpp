// `pvrt export-pov SCENE -o OUT.pov`: the scene in POV-Ray's language.
#include <cstdio>

#include "cli/commands.h"
#include "core/output_files.h"
#include "core/error.h"
#include "pov_export.h"
#include "scene/xml_loader.h"

namespace pvrt::cli {

namespace {

struct ExportOptions {
  std::string scene, output;
  bool strict = false;
  int aaDepth = 0;
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
  out.stageBytes(o.output, withRecipe(e.sdl, desc, PovRecipe{o.aaDepth, o.output == "-" ? "scene.pov" : o.output}));
  out.commit();
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
  return [o] { return runExport(*o); };
}

}  // namespace pvrt::cli
