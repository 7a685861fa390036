#include "app/convert_command.h"

#include <CLI/CLI.hpp>
#include <filesystem>
#include <iostream>

#include "app/cli.h"
#include "core/atomic_file.h"
#include "core/message_text.h"
#include "scene/document_save.h"
#include "scene/file_search.h"
#include "scene/scene_loader.h"
#include "scene/value_text.h"

namespace fs = std::filesystem;

namespace ray {

namespace {

const char* const kConvertUsage = R"(usage: ray convert <in> <out> [options]

Converts a scene between the CS123 XML format and the course's JSON (CS1230, 2023 on):
the format of <out> is its extension's (.json or .xml), that of <in> its text's. XML to
JSON: a transblock whose transforms are not in translate, rotate, scale, matrix order
becomes nested groups, masters become templates, lights become groups with a translate.
JSON to XML: templates become masters, lights are written where they are placed. The
converted scene renders as the original does. What the other format has no place for (a
torus, an area light, an emissive colour, csg, motion) is refused with its line, and
nothing is written; texture and mesh names are written relative to where <out> is.

options:
  --search-path DIR        also look for textures and meshes under DIR (repeatable;
                           RAY_SEARCH_PATH=dir1:dir2 does the same)
  --strict                 every warning (a texture not found) is an error
  --replace-read-only      replace <out> even when it is read-only
  -h, --help               this text

exit status: 0 success, 2 bad input or arguments (nothing is written), 3 <out> could not be
written
)";

struct ConvertOptions {
    std::vector<std::string> positionals;  // <in> <out>
    std::vector<fs::path> searchPaths;
    bool strict = false;
    bool replaceReadOnly = false;
    bool help = false;
};

void defineOptions(CLI::App& app, ConvertOptions& o) {
    app.set_help_flag();  // kConvertUsage instead of CLI11's
    addSwitch(app, "-h,--help", [&] { o.help = true; });
    app.add_option_function<std::vector<std::string>>("--search-path", [&](const std::vector<std::string>& dirs) {
        for (const std::string& dir : dirs) o.searchPaths.emplace_back(dir);
    })->expected(1)->multi_option_policy(CLI::MultiOptionPolicy::TakeAll);
    addSwitch(app, "--strict", [&] { o.strict = true; });
    addSwitch(app, "--replace-read-only", [&] { o.replaceReadOnly = true; });
    app.add_option("positionals", o.positionals);
}

const char* formatName(SceneFormat format) {
    return format == SceneFormat::Json ? "the course's JSON" : "CS123 XML";
}

// The format <out>'s name says; UsageError when it says none.
SceneFormat outputFormat(const fs::path& out) {
    const std::string extension = out.extension().string();
    if (sameName(extension.c_str(), ".json")) return SceneFormat::Json;
    if (sameName(extension.c_str(), ".xml")) return SceneFormat::Xml;
    throw UsageError("the format of '" + quotedForMessage(out.string()) +
                     "' is not known from its name: name it .json (the course's JSON) or .xml (CS123 XML)");
}

WriteOptions writeOptions(const ConvertOptions& o) {
    WriteOptions write;
    write.replaceReadOnly = o.replaceReadOnly;
    return write;
}

int convert(const ConvertOptions& o) {
    const fs::path in = o.positionals[0], out = o.positionals[1];
    const SceneFormat wanted = outputFormat(out);
    refuseWritingOverInput(out, "<out>", in, "the scene to convert");
    checkCanWrite(out, writeOptions(o));
    LoadOptions load;
    load.searchPaths = o.searchPaths;
    for (auto& p : searchPathsFromEnvironment()) load.searchPaths.push_back(p);
    load.strict = o.strict;
    load.loadImages = false;  // their names are converted, not their pixels
    load.warn = [](const std::string& message) { std::cerr << message << "\n"; };
    SceneDocument document = loadSceneDocument(in, load);
    if (document.format == wanted)
        throw UsageError("'" + quotedForMessage(in.string()) + "' is already " + formatName(wanted) +
                         ": nothing to convert (ray convert writes the other format)");
    // Flattened as a render would: what only flattening finds (an undefined or cyclic
    // master, a mesh that does not read) is refused in the input's terms.
    SceneDocument flattened = document;
    Resources resources;
    flattenDocument(flattened, resources, load);
    saveDocument(document, resources, out, writeOptions(o));
    std::cout << "ray convert: wrote " << quotedForMessage(out.string()) << " (" << formatName(wanted) << ") from "
              << quotedForMessage(in.string()) << " (" << formatName(document.format) << ")\n";
    return 0;
}

void finishOptions(const ConvertOptions& o) {
    if (o.positionals.empty()) throw UsageError("no scene file given: ray convert <in> <out>");
    if (o.positionals.size() < 2) throw UsageError("no output file given: ray convert <in> <out>");
    if (o.positionals.size() > 2) throw UsageError("too many arguments: '" + quotedForMessage(o.positionals[2]) + "'");
    outputFormat(o.positionals[1]);
}

}  // namespace

CommandReference convertCommandReference() {
    CLI::App app{"ray convert", "ray convert"};
    ConvertOptions options;
    defineOptions(app, options);
    return describeCommand("convert", app, kConvertUsage);
}

int runConvertCommand(const std::vector<std::string>& args) {
    CLI::App app{"ray convert", "ray convert"};
    ConvertOptions options;
    defineOptions(app, options);
    try {
        parseArguments(app, args);
        if (options.help) {
            std::cout << kConvertUsage;
            return 0;
        }
        finishOptions(options);
        return convert(options);
    } catch (const UsageError& e) {
        std::cerr << "ray convert: " << e.what() << "\n(see ray convert --help)\n";
        return 2;
    } catch (const InputError& e) {
        std::cerr << e.what() << "\n";
        return 2;
    } catch (const OutputRefused& e) {
        std::cerr << "ray convert: " << e.what() << "\n";
        return 2;
    } catch (const std::exception& e) {  // FileWriteError: the system's failure
        std::cerr << "ray convert: " << e.what() << "\n";
        return 3;
    }
}

}  // namespace ray
