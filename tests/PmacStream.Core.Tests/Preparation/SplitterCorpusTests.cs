using PmacStream.Preparation;
using Xunit.Abstractions;

namespace PmacStream.Core.Tests.Preparation;

/// <summary>Real CAM programs from ../shared/gcode-corpus (reported SKIPPED, with the reason, when the folder is absent).</summary>
public class SplitterCorpusTests(ITestOutputHelper output)
{
    [SkippableFact]
    public void Every_corpus_program_splits_into_valid_chunks()
    {
        var files = Requires.Corpus();
        files.Should().NotBeEmpty();
        foreach (var file in files)
        {
            using var tp = new TempProgram(File.ReadAllBytes(file), Path.GetFileName(file));
            var options = new SplitOptions { AllowErrors = true };
            var r = tp.Split(options);
            output.WriteLine($"{Path.GetFileName(file)}: {r.Manifest.Chunks.Count} chunks, {r.Manifest.TotalBlocks} blocks, {r.Manifest.TotalMotionBlocks} motion");
            r.Manifest.TotalBlocks.Should().BeGreaterThan(0, file);
            var markers = 0;
            var lastMarker = 0;
            foreach (var c in r.Manifest.Chunks)
            {
                var path = Path.Combine(r.OutputDirectory, c.FileName);
                var bytes = File.ReadAllBytes(path);
                bytes.Should().OnlyContain(b => b < 128, file);
                bytes.Length.Should().Be((int)c.ByteSize).And.BeLessThanOrEqualTo((int)options.MaxChunkBytes);
                c.BlockCount.Should().BeLessThanOrEqualTo(1000);
                c.EstimatedWords.Should().BeLessThanOrEqualTo(options.RotWords);
                ChunkText.Sha(path).Should().Be(c.Sha256);
                foreach (var line in ChunkText.Lines(path))
                {
                    line.Replace("F(P500)", "").Should().NotContain("(", file).And.NotContain(";").And.NotContain("%").And.NotStartWith("/").And.NotBeEmpty();
                    line.Should().MatchRegex(@"^(CLOSE|OPEN ROT|[A-Z][-0-9.]+|M[0-9]+==[0-9]+|P[0-9]+=[-0-9.]+|F\(P500\))( ([A-Z][-0-9.]+|M[0-9]+==[0-9]+|F\(P500\)|DWELL0))*$", file);
                    if (line.StartsWith("M0==", StringComparison.Ordinal))
                    {
                        var n = int.Parse(line[4..line.IndexOf(' ')], System.Globalization.CultureInfo.InvariantCulture);
                        n.Should().BeGreaterThan(lastMarker, "markers follow source order").And.BeInRange(c.FirstSourceLine, c.LastSourceLine);
                        lastMarker = n;
                        markers++;
                    }
                }
            }

            markers.Should().Be(r.Manifest.TotalMotionBlocks, file);
        }
    }
}
