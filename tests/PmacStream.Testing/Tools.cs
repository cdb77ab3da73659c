namespace PmacStream.Testing;

/// <summary>Finds an external tool the way a shell does, on PATH, so hiding it from PATH hides it from the tests.</summary>
public static class Tools
{
    /// <summary>The full path of an executable named <paramref name="name"/> on PATH (or on <paramref name="searchPath"/>), or null.</summary>
    public static string? Find(string name, string? searchPath = null)
    {
        var path = searchPath ?? Environment.GetEnvironmentVariable("PATH") ?? string.Empty;
        foreach (var dir in path.Split(System.IO.Path.PathSeparator, StringSplitOptions.RemoveEmptyEntries))
        {
            string[] candidates = OperatingSystem.IsWindows() ? [name + ".exe", name] : [name];
            foreach (var candidate in candidates)
            {
                var full = System.IO.Path.Combine(dir, candidate);
                if (File.Exists(full) && (OperatingSystem.IsWindows() || (File.GetUnixFileMode(full) & (UnixFileMode.UserExecute | UnixFileMode.GroupExecute | UnixFileMode.OtherExecute)) != 0))
                {
                    return full;
                }
            }
        }

        return null;
    }
}
