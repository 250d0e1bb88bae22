// STUB: not Unity's code, and not Unity's compiler.
//
// A small stand-in, written for relief's tests, for the declarations a Shader Graph Custom
// Function (File mode) sees on a D3D-style platform: the texture and sampler macros of the
// render pipelines' core shader library and the `UnityTexture2D`, `UnityTexture3D` and
// `UnitySamplerState` structs of its Texture.hlsl, with the members Unity documents for
// them (`tex`, `samplerstate`, `texelSize`, `scaleTranslate`) and the builder macros
// Shader Graph's generated code uses. Their member functions (Sample, Load, …) are left out:
// relief's functions take `.tex` and `.samplerstate` and call the HLSL methods themselves.
// A file that compiles against this stub with glslang's HLSL front end may still meet a
// difference in Unity's real headers: that is the gap of this check.

#define TEXTURE2D(textureName) Texture2D textureName
#define TEXTURE3D(textureName) Texture3D textureName
#define SAMPLER(samplerName) SamplerState samplerName

struct UnitySamplerState
{
    SAMPLER(samplerstate);
};

struct UnityTexture2D
{
    TEXTURE2D(tex);
    SAMPLER(samplerstate);
    float4 texelSize;
    float4 scaleTranslate;
};

struct UnityTexture3D
{
    TEXTURE3D(tex);
    SAMPLER(samplerstate);
};

UnityTexture2D UnityBuildTexture2DStructInternal(TEXTURE2D(tex), SAMPLER(samplerstate), float4 texelSize, float4 scaleTranslate)
{
    UnityTexture2D result;
    result.tex = tex;
    result.samplerstate = samplerstate;
    result.texelSize = texelSize;
    result.scaleTranslate = scaleTranslate;
    return result;
}

UnityTexture3D UnityBuildTexture3DStructInternal(TEXTURE3D(tex), SAMPLER(samplerstate))
{
    UnityTexture3D result;
    result.tex = tex;
    result.samplerstate = samplerstate;
    return result;
}

UnitySamplerState UnityBuildSamplerStateStruct(SAMPLER(samplerstate))
{
    UnitySamplerState result;
    result.samplerstate = samplerstate;
    return result;
}

// A texture property `_Name` comes with `sampler_Name`, `_Name_TexelSize` and `_Name_ST`.
#define UnityBuildTexture2DStructNoScale(n) UnityBuildTexture2DStructInternal(n, sampler##n, n##_TexelSize, float4(1, 1, 0, 0))
#define UnityBuildTexture3DStruct(n) UnityBuildTexture3DStructInternal(n, sampler##n)
