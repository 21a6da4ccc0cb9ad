// windloom → Unity: applies a bake's manifest.json to its VF files and follows re-bakes.
//
// Put this file in an Editor folder of your project (e.g. Assets/Windloom/Editor/) and bake
// into the project (windloom bake level.json --out Assets/Wind --format vf --format dds).
// Then select the bake folder and choose Assets → windloom → Apply Bake Settings: every VF
// file the manifest's engines.unity block lists gets its importer's Output Format, Wrap Mode
// and Filter Mode (Float, Clamp, Bilinear) and is reimported. Assets → windloom → Follow
// Re-bakes polls the folder's manifest.json twice a second while the editor runs and, when its
// sequence changes (windloom bake --watch, or the windloom editor's Live export), refreshes
// the asset database and applies the settings again. The VFX Graph block settings (Signed,
// Closed Field, box centre and size) are set on the scene's WindloomVectorField component.
#if UNITY_EDITOR
using System;
using System.IO;
using UnityEditor;
using UnityEngine;

public static class WindloomImport
{
    [Serializable] public class VfImport { public string output_format; public string wrap_mode; public string filter_mode; }
    [Serializable] public class VectorField { public string[] files; public VfImport import; }
    [Serializable] public class Unity { public VectorField vector_field; public VectorField volume; }
    [Serializable] public class Engines { public Unity unity; }
    [Serializable] public class Manifest { public string format; public long sequence; public Engines engines; }

    const string FollowKey = "windloom.follow";

    /// The manifest of the bake in `dir` (a project-relative folder), or null.
    public static Manifest Read(string dir)
    {
        var path = Path.Combine(dir, "manifest.json");
        if (!File.Exists(path)) return null;
        var m = JsonUtility.FromJson<Manifest>(File.ReadAllText(path));
        return m != null && m.format == "windloom-bake" ? m : null;
    }

    /// Applies the manifest's importer settings to each VF file of the bake; how many.
    public static int Apply(string dir)
    {
        var m = Read(dir);
        if (m == null) throw new InvalidOperationException($"windloom: {dir} holds no windloom manifest.json");
        var unity = m.engines?.unity;
        if (unity == null) throw new InvalidOperationException("windloom: this bake has no file Unity reads; bake vf or dds");
        int count = 0;
        foreach (var field in new[] { unity.vector_field, unity.volume })
        {
            if (field?.files == null) continue;
            foreach (var name in field.files)
            {
                if (!name.EndsWith(".vf")) continue;
                var path = dir.TrimEnd('/') + "/" + name;
                AssetDatabase.ImportAsset(path);
                var importer = AssetImporter.GetAtPath(path);
                if (importer == null) { Debug.LogWarning($"windloom: no importer for {path} (is the Visual Effect Graph package installed?)"); continue; }
                var so = new SerializedObject(importer);
                so.FindProperty("m_OutputFormat").intValue = field.import.output_format == "Float" ? 0 : 1;
                so.FindProperty("m_WrapMode").intValue = (int)Enum.Parse(typeof(TextureWrapMode), field.import.wrap_mode);
                so.FindProperty("m_FilterMode").intValue = (int)Enum.Parse(typeof(FilterMode), field.import.filter_mode);
                so.ApplyModifiedPropertiesWithoutUndo();
                importer.SaveAndReimport();
                count++;
            }
        }
        Debug.Log($"windloom: applied bake {m.sequence} to {count} vector field(s) in {dir}");
        return count;
    }

    static string SelectedFolder()
    {
        var path = AssetDatabase.GetAssetPath(Selection.activeObject);
        return AssetDatabase.IsValidFolder(path) ? path : Path.GetDirectoryName(path)?.Replace('\\', '/');
    }

    [MenuItem("Assets/windloom/Apply Bake Settings")]
    static void ApplySelected() => Apply(SelectedFolder());

    [MenuItem("Assets/windloom/Follow Re-bakes")]
    static void Follow()
    {
        EditorPrefs.SetString(FollowKey, SelectedFolder());
        last = -1;
    }

    [MenuItem("Assets/windloom/Stop Following")]
    static void Stop() => EditorPrefs.DeleteKey(FollowKey);

    static long last = -1;
    static double nextLook;

    [InitializeOnLoadMethod]
    static void Watch()
    {
        EditorApplication.update += () =>
        {
            if (EditorApplication.timeSinceStartup < nextLook || !EditorPrefs.HasKey(FollowKey)) return;
            nextLook = EditorApplication.timeSinceStartup + 0.5;
            var dir = EditorPrefs.GetString(FollowKey);
            var m = Read(dir);
            if (m == null || m.sequence == last) return;
            AssetDatabase.Refresh();
            Apply(dir);
            // Keep it only if no other bake landed while importing: else look again.
            var again = Read(dir);
            if (again != null && again.sequence == m.sequence) last = m.sequence;
        };
    }
}
#endif
