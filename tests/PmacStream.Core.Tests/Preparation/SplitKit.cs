using System.Security.Cryptography;
using System.Text;
using PmacStream.Preparation;

namespace PmacStream.Core.Tests.Preparation;

/// <summary>A temporary folder holding a source program; deleted on dispose.</summary>
internal sealed class TempProgram : IDisposable
{
    private readonly TestFolder _temp = new("split");

    public TempProgram(string text, string name = "prog.nc")
        : this(Encoding.UTF8.GetBytes(text), name)
    {
    }

    public TempProgram(byte[] bytes, string name = "prog.nc")
    {
        Folder = _temp.Path;
        SourcePath = Path.Combine(Folder, name);
        File.WriteAllBytes(SourcePath, bytes);
    }

    public string Folder { get; }

    public string SourcePath { get; }

    public string OutDir => Path.Combine(Folder, "out");

    public SplitResult Split(SplitOptions? options = null) =>
        Splitter.Split(SourcePath, (options ?? new SplitOptions()) with { OutDir = OutDir });

    public void Dispose() => _temp.Dispose();
}

/// <summary>Reads chunk files back and undoes the splitter's annotations.</summary>
internal static class ChunkText
{
    public static string[] Lines(string path)
    {
        var text = File.ReadAllText(path, Encoding.ASCII);
        text.Should().EndWith("\r\n");
        text.Replace("\r\n", "").Should().NotContain("\r").And.NotContain("\n", "every line ends in CR LF");
        return text[..^2].Split("\r\n");
    }

    /// <summary>All program lines of every chunk (header, footer and tail removed), in order.</summary>
    public static List<string> Body(SplitResult r, SplitOptions o)
    {
        var all = new List<string>();
        var tail = o.ProgramTail.Split('\n').Select(t => t.Trim()).Where(t => t.Length > 0).ToList();
        var chunks = r.ChunkPaths.ToList();
        for (var i = 0; i < chunks.Count; i++)
        {
            var lines = Lines(chunks[i]).ToList();
            lines[0].Should().Be("CLOSE");
            lines[1].Should().Be("OPEN ROT");
            lines[^1].Should().Be("CLOSE");
            lines = lines.Skip(2).SkipLast(1).ToList();
            if (i == chunks.Count - 1 && tail.Count > 0)
            {
                // Tail either last, or right before a final M02/M30 block (so the end code still ends the program).
                var last = lines[^1];
                var endsProgram = !last.Contains("==") && last.Split(' ').Any(t =>
                    System.Text.RegularExpressions.Regex.IsMatch(t, @"^M0*(2|30)(\.0*)?$"));
                var at = endsProgram ? lines.Count - 1 - tail.Count : lines.Count - tail.Count;
                lines.Skip(at).Take(tail.Count).Should().Equal(tail, "the program tail is in the last chunk");
                lines.RemoveRange(at, tail.Count);
            }

            all.AddRange(lines);
        }

        return all;
    }

    public static string Sha(string path) => Convert.ToHexStringLower(SHA256.HashData(File.ReadAllBytes(path)));
}
