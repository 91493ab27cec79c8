// Kajiya-Kay hair strands with the wet look, for D3D hosts (Unreal, Unity): the same shading
// as kajiya_kay.vert/.frag (see there for the vertex layout). Entry points VSMain and PSMain;
// draw the vertex buffer as a line list.

cbuffer KajiyaKay : register(b0)
{
    float4x4 view_proj;   // world -> clip, column vectors (mul(view_proj, p))
    float4 eye;
    float4 light;
};

struct VertexIn
{
    float3 position : POSITION;
    float3 tangent : TANGENT;
    float wetness : TEXCOORD0;
};

struct VertexOut
{
    float4 clip : SV_Position;
    float3 tangent : TEXCOORD0;
    float3 to_eye : TEXCOORD1;
    float wetness : TEXCOORD2;
};

VertexOut VSMain(VertexIn v)
{
    VertexOut o;
    o.clip = mul(view_proj, float4(v.position, 1.0));
    o.tangent = v.tangent;
    o.to_eye = eye.xyz - v.position;
    o.wetness = v.wetness;
    return o;
}

float3 kajiya_kay(float3 t, float3 l, float3 v, float wet)
{
    float lt = dot(l, t);
    float vt = dot(v, t);
    float sin_l = sqrt(max(0.0, 1.0 - lt * lt));
    float sin_v = sqrt(max(0.0, 1.0 - vt * vt));
    float shininess = 30.0 + 120.0 * wet;
    float spec = pow(max(sin_l * sin_v - lt * vt, 0.0), shininess) * (0.25 + 0.75 * wet);
    float3 base = float3(0.30, 0.15, 0.06) * (1.0 - 0.6 * wet);
    float diffuse = 0.2 + 0.8 * sin_l;
    return base * diffuse + spec * float3(1.0, 1.0, 0.95);
}

float4 PSMain(VertexOut i) : SV_Target
{
    float3 c = kajiya_kay(normalize(i.tangent), normalize(light.xyz), normalize(i.to_eye), saturate(i.wetness));
    return float4(pow(saturate(c), 1.0 / 2.2), 1.0);
}
