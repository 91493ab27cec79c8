#include "Interfaces/IPluginManager.h"
#include "Misc/Paths.h"
#include "Modules/ModuleManager.h"
#include "wethair.h"

// Loads the delay-loaded DLL from the plugin's binaries on Windows before any call into it;
// elsewhere the loader finds the staged library by its rpath/SONAME.
class FWetHairModule : public IModuleInterface
{
public:
    virtual void StartupModule() override
    {
#if PLATFORM_WINDOWS
        const FString Dir = FPaths::Combine(IPluginManager::Get().FindPlugin(TEXT("WetHair"))->GetBaseDir(), TEXT("Binaries/Win64"));
        Handle = FPlatformProcess::GetDllHandle(*FPaths::Combine(Dir, TEXT("wethair.dll")));
        if (!Handle) UE_LOG(LogTemp, Error, TEXT("wethair: could not load wethair.dll from %s"), *Dir);
#endif
        UE_LOG(LogTemp, Log, TEXT("wethair %s"), UTF8_TO_TCHAR(wethair_version_string()));
    }

    virtual void ShutdownModule() override
    {
        if (Handle) FPlatformProcess::FreeDllHandle(Handle);
        Handle = nullptr;
    }

private:
    void* Handle = nullptr;
};

IMPLEMENT_MODULE(FWetHairModule, WetHair)
