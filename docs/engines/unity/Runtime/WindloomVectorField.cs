// windloom → Unity: places a VFX Graph's vector field box as the bake's manifest says.
//
// Add it to the GameObject holding a VisualEffect whose graph has a Vector Field Force block
// reading an exposed Texture3D, and exposed Vector3 properties for the block's Field
// Transform position and scale (names below). Give it the bake's manifest.json (a TextAsset)
// and the imported vector field. It sets the field, the box's centre and size from
// engines.unity (vector_field, or volume with useVolume), and the graph then gives the baked
// wind in m/s with the block's Data Encoding set to Signed and Closed Field on
// (docs/engines/unity.md). An animated bake plays: give every frame's imported field, in
// order, to `frames`; they are set one after another at the bake's fps (the manifest's
// frames.fps), looping when the bake loops.
using System;
using UnityEngine;
using UnityEngine.VFX;

[RequireComponent(typeof(VisualEffect))]
public class WindloomVectorField : MonoBehaviour
{
    public TextAsset manifest;
    public Texture3D vectorField;
    public bool useVolume;
    public string fieldProperty = "WindField";
    public string centreProperty = "WindBoxCenter";
    public string sizeProperty = "WindBoxSize";
    [Tooltip("An animated bake: every frame's imported field in order (wind_0000.vf, wind_0001.vf, …), played at the bake's fps. Empty: vectorField alone.")]
    public Texture3D[] frames = Array.Empty<Texture3D>();

    float fps = 30f;
    bool loops = true;
    float clock;
    int shown = -1;
    VisualEffect vfx;

    [Serializable] class Field { public float[] box_center; public float[] box_size; public string data_encoding; }
    [Serializable] class UnityBlock { public Field vector_field; public Field volume; }
    [Serializable] class Engines { public UnityBlock unity; }
    [Serializable] class Frames { public float fps; public bool loop; }
    [Serializable] class Manifest { public Frames frames; public Engines engines; }

    void OnEnable() => Apply();

    void OnValidate() { if (isActiveAndEnabled) Apply(); }

    public void Apply()
    {
        if (manifest == null) return;
        var m = JsonUtility.FromJson<Manifest>(manifest.text);
        var unity = m?.engines?.unity;
        if (m?.frames != null && m.frames.fps > 0f) { fps = m.frames.fps; loops = m.frames.loop; }
        var field = useVolume ? unity?.volume : unity?.vector_field;
        if (field?.box_center == null || field.box_center.Length != 3)
        {
            Debug.LogWarning("windloom: the manifest has no " + (useVolume ? "volume (bake dds)" : "vector field (bake vf)"), this);
            return;
        }
        vfx = GetComponent<VisualEffect>();
        shown = -1;
        if (vectorField != null) vfx.SetTexture(fieldProperty, vectorField);
        vfx.SetVector3(centreProperty, new Vector3(field.box_center[0], field.box_center[1], field.box_center[2]));
        vfx.SetVector3(sizeProperty, new Vector3(field.box_size[0], field.box_size[1], field.box_size[2]));
    }

    // Frame k = floor(time · fps) of `frames`, wrapped when the bake loops, else held at the
    // last; the texture is set only when the frame changes.
    void Update()
    {
        if (frames == null || frames.Length < 2 || vfx == null) return;
        clock += Time.deltaTime;
        int n = frames.Length;
        int k = Mathf.FloorToInt(clock * fps);
        k = loops ? ((k % n) + n) % n : Mathf.Min(k, n - 1);
        if (k == shown || frames[k] == null) return;
        vfx.SetTexture(fieldProperty, frames[k]);
        shown = k;
    }
}
