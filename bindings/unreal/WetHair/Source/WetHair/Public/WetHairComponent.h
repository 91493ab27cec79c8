// A component that runs a wethair simulation: the owner's transform is the head, the strands
// come from a .tfx/.hair file or the paper scene, colliders may ride on the owner's bones,
// water is sprayed from Blueprint, and the
// vertices are copied out every tick (copy path) for a renderer (Niagara ribbons, a custom
// mesh, a compute shader) to draw.
#pragma once

#include "Components/ActorComponent.h"
#include "CoreMinimal.h"
#include "WetHairComponent.generated.h"

struct WetHairSim;

/** A sphere or capsule on a bone of the owner's skeletal mesh (a shoulder, the collar, the
 * back): it moves with that bone, not with the head. */
USTRUCT(BlueprintType)
struct FWetHairBoneCollider
{
    GENERATED_BODY()

    /** The bone (or socket) of the owner's skeletal mesh the collider rides on. */
    UPROPERTY(EditAnywhere, Category = "WetHair")
    FName Bone;

    /** Capsule axis ends in the bone's space, cm (equal ends: a sphere). */
    UPROPERTY(EditAnywhere, Category = "WetHair")
    FVector A = FVector::ZeroVector;

    UPROPERTY(EditAnywhere, Category = "WetHair")
    FVector B = FVector::ZeroVector;

    /** Radius, cm. */
    UPROPERTY(EditAnywhere, Category = "WetHair")
    float Radius = 5.f;
};

UCLASS(ClassGroup = (Physics), meta = (BlueprintSpawnableComponent))
class WETHAIR_API UWetHairComponent : public UActorComponent
{
    GENERATED_BODY()

public:
    UWetHairComponent();

    /** A .tfx or .hair file (absolute, or relative to the project's Content folder); empty: the paper scene. */
    UPROPERTY(EditAnywhere, Category = "WetHair")
    FString HairFile;

    /** Mass of one hair point, kg. */
    UPROPERTY(EditAnywhere, Category = "WetHair")
    float PointMass = 1e-3f;

    /** Run on the GPU where a hardware adapter is found (wethair's AUTO), else the CPU. */
    UPROPERTY(EditAnywhere, Category = "WetHair")
    bool bAllowGpu = true;

    /** Colliders on bones of the owner's skeletal mesh, beside the head sphere (wethair's
     * collider frames: each frame is set from its bone every tick). */
    UPROPERTY(EditAnywhere, Category = "WetHair")
    TArray<FWetHairBoneCollider> BoneColliders;

    /** Adds Count particles in a cone of half-angle ConeDegrees from Origin along Direction at Speed (cm/s). */
    UFUNCTION(BlueprintCallable, Category = "WetHair")
    void Spray(FVector Origin, FVector Direction, float Speed, float ConeDegrees, int32 Count);

    /** Removes every water particle. */
    UFUNCTION(BlueprintCallable, Category = "WetHair")
    void ClearWater();

    /** Vertices of the last step: position (cm, world), tangent, wetness, per hair point. */
    const TArray<float>& GetVertices() const { return Vertices; }
    int32 GetStrideFloats() const { return StrideFloats; }

    virtual void TickComponent(float DeltaTime, ELevelTick TickType, FActorComponentTickFunction* ThisTickFunction) override;

protected:
    virtual void BeginPlay() override;
    virtual void EndPlay(const EEndPlayReason::Type Reason) override;

private:
    /** Each collider's frame as wethair's column-major 4x4s: the head, then each bone's. */
    void FillColliderFrames(float* Frames) const;

    WetHairSim* Sim = nullptr;
    UPROPERTY()
    class USkeletalMeshComponent* Mesh = nullptr;
    /** The colliders' frames of the tick (kept: no allocation per tick). */
    TArray<float> Frames;
    TArray<float> Vertices;
    int32 StrideFloats = 0;
    uint32 Seed = 1;
};
