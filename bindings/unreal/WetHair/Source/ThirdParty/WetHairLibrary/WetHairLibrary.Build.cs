// The prebuilt wethair library as an External module: headers, the import/shared library to
// link, and the runtime file staged next to the binaries. Expects scripts/dist.sh's layout,
// copied (or linked) to Source/ThirdParty/WetHairLibrary/dist/ for each platform:
//   dist/<Platform>/include/wethair/wethair.h, wethair.hpp
//   dist/<Platform>/lib/libwethair.so.0.1 (Linux), libwethair.dylib (Mac), wethair.dll + wethair.dll.lib (Win64)
using System.IO;
using UnrealBuildTool;

public class WetHairLibrary : ModuleRules
{
    public WetHairLibrary(ReadOnlyTargetRules Target) : base(Target)
    {
        Type = ModuleType.External;
        string Dist = Path.Combine(ModuleDirectory, "dist", Target.Platform.ToString());
        PublicSystemIncludePaths.Add(Path.Combine(Dist, "include", "wethair"));
        string Lib = Path.Combine(Dist, "lib");

        if (Target.Platform == UnrealTargetPlatform.Win64)
        {
            PublicAdditionalLibraries.Add(Path.Combine(Lib, "wethair.dll.lib"));
            // Loaded on first use, from the plugin's Binaries folder (see FWetHairModule).
            PublicDelayLoadDLLs.Add("wethair.dll");
            RuntimeDependencies.Add("$(BinaryOutputDir)/wethair.dll", Path.Combine(Lib, "wethair.dll"));
        }
        else if (Target.Platform == UnrealTargetPlatform.Linux)
        {
            // The SONAME is libwethair.so.0.1: stage that file; the linker takes libwethair.so.
            PublicAdditionalLibraries.Add(Path.Combine(Lib, "libwethair.so"));
            RuntimeDependencies.Add("$(BinaryOutputDir)/libwethair.so.0.1", Path.Combine(Lib, "libwethair.so.0.1"));
        }
        else if (Target.Platform == UnrealTargetPlatform.Mac)
        {
            PublicAdditionalLibraries.Add(Path.Combine(Lib, "libwethair.dylib"));
            RuntimeDependencies.Add("$(BinaryOutputDir)/libwethair.dylib", Path.Combine(Lib, "libwethair.dylib"));
        }
    }
}
