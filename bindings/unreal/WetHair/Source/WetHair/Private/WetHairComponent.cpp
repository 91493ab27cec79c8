#include "WetHairComponent.h"

#include "Components/SkeletalMeshComponent.h"
#include "Misc/Paths.h"
#include "wethair.h"

namespace
{
// wethair works in metres with z up, like Unreal's axes but in centimetres.
constexpr float CmToM = 0.01f;

// A transform as wethair's column-major 4x4, its translation in metres.
void ToColumns(FTransform T, float Cols[16])
{
    T.SetTranslation(T.GetTranslation() * CmToM);
    const FMatrix M = T.ToMatrixWithScale();
    for (int32 C = 0; C < 4; C++)
        for (int32 R = 0; R < 4; R++) Cols[4 * C + R] = float(M.M[C][R]); // FMatrix acts on row vectors: its rows are our columns
}

bool Check(WetHairResult R, const TCHAR* What)
{
    if (R == WETHAIR_OK) return true;
    UE_LOG(LogTemp, Error, TEXT("wethair: %s failed: %s"), What, UTF8_TO_TCHAR(wethair_last_error_message()));
    return false;
}
} // namespace

UWetHairComponent::UWetHairComponent()
{
    PrimaryComponentTick.bCanEverTick = true;
    PrimaryComponentTick.TickGroup = TG_PrePhysics;
}

void UWetHairComponent::BeginPlay()
{
    Super::BeginPlay();
    WetHairGroom* Groom = nullptr;
    if (HairFile.IsEmpty())
    {
        if (!Check(wethair_groom_create_paper_scene(10000, 6, &Groom), TEXT("paper scene"))) return;
    }
    else
    {
        const FString Path = FPaths::IsRelative(HairFile) ? FPaths::ProjectContentDir() / HairFile : HairFile;
        if (!Check(wethair_groom_load(TCHAR_TO_UTF8(*Path), PointMass, &Groom), TEXT("groom load"))) return;
    }
    // The current defaults (material springs, AUTO integrator), right for any groom.
    WetHairSimDesc Desc;
    if (!Check(wethair_sim_desc_init(&Desc, sizeof Desc), TEXT("desc init"))) return;
    // The head sphere first; with bone colliders every collider is on a frame of its own, the
    // head's being the owner's transform (set each tick, as the head transform is).
    TArray<WetHairCollider> Colliders;
    Colliders.Add({WETHAIR_COLLIDER_SPHERE, {0, 0, 0}, {0, 0, 0}, 0.1f});
    for (const FWetHairBoneCollider& C : BoneColliders)
    {
        const FVector A = C.A * CmToM, B = C.B * CmToM;
        Colliders.Add({WETHAIR_COLLIDER_CAPSULE, {float(A.X), float(A.Y), float(A.Z)}, {float(B.X), float(B.Y), float(B.Z)},
                       C.Radius * CmToM});
    }
    Mesh = GetOwner()->FindComponentByClass<USkeletalMeshComponent>();
    if (BoneColliders.Num() > 0 && !Mesh)
        UE_LOG(LogTemp, Warning, TEXT("wethair: BoneColliders need a skeletal mesh on the owner; they stay where they start"));
    Frames.SetNumZeroed(16 * Colliders.Num());
    FillColliderFrames(Frames.GetData());
    Desc.groom = Groom;
    Desc.colliders = Colliders.GetData();
    Desc.collider_count = uint32(Colliders.Num());
    Desc.collider_frames = BoneColliders.Num() > 0 ? Frames.GetData() : nullptr;
    Desc.backend = bAllowGpu ? WETHAIR_BACKEND_AUTO : WETHAIR_BACKEND_CPU;
    Check(wethair_sim_create(&Desc, &Sim), TEXT("simulation create"));
    wethair_groom_destroy(Groom);
    if (!Sim) return;
    WetHairVertexLayout Layout = {};
    Layout.struct_size = sizeof Layout;
    if (Check(wethair_sim_get_vertex_layout(Sim, &Layout), TEXT("vertex layout")))
    {
        StrideFloats = int32(Layout.stride_floats);
        Vertices.SetNumZeroed(int32(Layout.vertex_count * Layout.stride_floats));
    }
}

void UWetHairComponent::TickComponent(float DeltaTime, ELevelTick TickType, FActorComponentTickFunction* ThisTickFunction)
{
    Super::TickComponent(DeltaTime, TickType, ThisTickFunction);
    if (!Sim || DeltaTime <= 0.f) return;
    // The head: the owner's transform, translation in metres, column-major.
    float Cols[16];
    ToColumns(GetOwner()->GetActorTransform(), Cols);
    Check(wethair_sim_set_head_transform(Sim, Cols), TEXT("head transform"));
    if (BoneColliders.Num() > 0)
    {
        if (Frames.Num() != 16 * (BoneColliders.Num() + 1)) Frames.SetNumZeroed(16 * (BoneColliders.Num() + 1));
        FillColliderFrames(Frames.GetData());
        for (int32 I = 0; I <= BoneColliders.Num(); I++)
            Check(wethair_sim_set_collider_transform(Sim, uint32(I), Frames.GetData() + 16 * I), TEXT("collider transform"));
    }
    if (!Check(wethair_sim_step(Sim, FMath::Min(DeltaTime, 1.f / 15.f)), TEXT("step"))) return;
    size_t Written = 0;
    Check(wethair_sim_get_vertex_buffer(Sim, Vertices.GetData(), size_t(Vertices.Num()), &Written), TEXT("vertices"));
}

void UWetHairComponent::FillColliderFrames(float* Frames) const
{
    // Collider 0 is the head sphere on the owner's transform; each bone collider on its bone
    // (the owner's transform where there is no mesh). Bones carry a uniform scale, as wethair
    // requires of a frame.
    const FTransform Head = GetOwner()->GetActorTransform();
    ToColumns(Head, Frames);
    for (int32 I = 0; I < BoneColliders.Num(); I++)
        ToColumns(Mesh ? Mesh->GetSocketTransform(BoneColliders[I].Bone, RTS_World) : Head, Frames + 16 * (I + 1));
}

void UWetHairComponent::Spray(FVector Origin, FVector Direction, float Speed, float ConeDegrees, int32 Count)
{
    if (!Sim || Count <= 0) return;
    TArray<float> Pos, Vel;
    Pos.Reserve(3 * Count);
    Vel.Reserve(3 * Count);
    FRandomStream Rng(int32(Seed++));
    for (int32 I = 0; I < Count; I++)
    {
        const FVector D = Rng.VRandCone(Direction.GetSafeNormal(), FMath::DegreesToRadians(ConeDegrees));
        const FVector P = Origin * CmToM, V = D * Speed * CmToM;
        Pos.Append({float(P.X), float(P.Y), float(P.Z)});
        Vel.Append({float(V.X), float(V.Y), float(V.Z)});
    }
    Check(wethair_sim_add_water(Sim, Pos.GetData(), Vel.GetData(), uint32(Count)), TEXT("add water"));
}

void UWetHairComponent::ClearWater()
{
    if (Sim) Check(wethair_sim_clear_water(Sim), TEXT("clear water"));
}

void UWetHairComponent::EndPlay(const EEndPlayReason::Type Reason)
{
    wethair_sim_destroy(Sim);
    Sim = nullptr;
    Super::EndPlay(Reason);
}
