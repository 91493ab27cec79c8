using UnrealBuildTool;

public class WetHair : ModuleRules
{
    public WetHair(ReadOnlyTargetRules Target) : base(Target)
    {
        PCHUsage = PCHUsageMode.UseExplicitOrSharedPCHs;
        PublicDependencyModuleNames.AddRange(new[] { "Core", "CoreUObject", "Engine", "WetHairLibrary" });
        PrivateDependencyModuleNames.AddRange(new[] { "Projects" });
    }
}
