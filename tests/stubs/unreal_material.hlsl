// STUB: not Unreal's code, and not Unreal's shader compiler.
//
// A small stand-in, written for relief's tests, for what the code of an Unreal Custom
// material expression sees: the view uniform buffer's shared samplers, under the names
// Unreal's view parameters give them (`View.SharedPointWrappedSampler`, …). Unreal's
// material translator pastes the node's code into a function whose parameters are the
// node's inputs (a Texture Object input `Name` arrives as `Texture2D Name` and
// `SamplerState NameSampler`) and whose additional outputs are `inout` parameters; the test
// builds that function around the node's code the same way. A file that compiles against
// this stub with glslang's HLSL front end may still meet a difference in Unreal's real
// material template: that is the gap of this check.

struct FViewStub
{
    SamplerState SharedPointWrappedSampler;
    SamplerState SharedPointClampedSampler;
    SamplerState SharedBilinearWrappedSampler;
    SamplerState SharedBilinearClampedSampler;
};

FViewStub View;
