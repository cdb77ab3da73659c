using System.Text;
using PmacStream.Preparation;

namespace PmacStream.Core.Tests.Preparation;

/// <summary>
/// Seeded random programs and limits. The generator knows what every line is (its words, F, whether it moves or
/// dwells), so it is the oracle: strip the splitter's annotations and the source blocks must come back exactly once,
/// in order, with the tracking marker on exactly the motion blocks and in the right place.
/// </summary>
public class SplitterPropertyTests
{
    private sealed record Expected(int Line, string Words, string? Feed, bool Motion, bool Dwell, bool EndsProgram);

    private static (byte[] Bytes, List<Expected> Blocks) Generate(Random rnd, int lineCount, bool blockDelete)
    {
        var sb = new StringBuilder();
        var expected = new List<Expected>();
        string Num()
        {
            var v = (rnd.NextDouble() * 400) - 200;
            return rnd.Next(4) switch
            {
                0 => ((int)v).ToString(System.Globalization.CultureInfo.InvariantCulture),
                1 => ((int)v).ToString(System.Globalization.CultureInfo.InvariantCulture) + ".",
                _ => v.ToString("0.###", System.Globalization.CultureInfo.InvariantCulture),
            };
        }

        for (var line = 1; line <= lineCount; line++)
        {
            var tokens = new List<(char L, string N)>();
            string? feed = null;
            var motion = false;
            var dwell = false;
            var ends = false;
            var prefix = "";
            var comment = "";
            var kind = rnd.Next(20);
            switch (kind)
            {
                case 0:
                    sb.Append(rnd.Next(2) == 0 ? "" : "   ").Append(rnd.Next(2) == 0 ? "(注释 中文 刀具)" : "; just a comment");
                    goto EndLine;
                case 1:
                    // A tape mark opens the tape only before any block; a later one would end it (FANUC, RS274/NGC).
                    sb.Append(line == 1 ? "%" : "");
                    goto EndLine;
                case 2:
                    sb.Append("O").Append(rnd.Next(1, 9999)).Append(" (PROGRAM 程序)");
                    goto EndLine;
                case 3:
                    // Block delete line.
                    tokens.Add(('G', "1"));
                    tokens.Add(('X', Num()));
                    prefix = "/";
                    motion = true;
                    break;
                case 4:
                    tokens.Add(('G', "04"));
                    tokens.Add(('P', rnd.Next(1, 2000).ToString(System.Globalization.CultureInfo.InvariantCulture)));
                    dwell = true;
                    break;
                case 5:
                    tokens.Add(('G', "92"));
                    tokens.Add(('X', "0"));
                    tokens.Add(('Y', "0"));
                    break;
                case 6:
                    tokens.Add(('M', rnd.Next(2) == 0 ? "03" : "08"));
                    tokens.Add(('S', rnd.Next(100, 20000).ToString(System.Globalization.CultureInfo.InvariantCulture)));
                    break;
                case 7:
                    feed = rnd.Next(10, 3000) + ".";
                    break;
                case 8:
                    tokens.Add(('G', "90"));
                    tokens.Add(('G', "17"));
                    break;
                case 9:
                    // N only: nothing for the controller.
                    sb.Append('N').Append(line * 10);
                    goto EndLine;
                case 10:
                    tokens.Add(('M', "30"));
                    ends = true;
                    break;
                case 11:
                    tokens.Add(('G', rnd.Next(2) == 0 ? "02" : "03"));
                    tokens.Add(('X', Num()));
                    tokens.Add(('Y', Num()));
                    tokens.Add(('I', Num()));
                    tokens.Add(('J', Num()));
                    motion = true;
                    break;
                default:
                    if (rnd.Next(3) == 0)
                    {
                        tokens.Add(('G', rnd.Next(2).ToString(System.Globalization.CultureInfo.InvariantCulture)));
                    }

                    foreach (var axis in "XYZABC")
                    {
                        if (rnd.Next(3) == 0 || (axis == 'C' && !motion))
                        {
                            tokens.Add((axis, Num()));
                            motion = true;
                        }
                    }

                    break;
            }

            if (!dwell && rnd.Next(6) == 0)
            {
                feed ??= rnd.Next(10, 3000).ToString(System.Globalization.CultureInfo.InvariantCulture);
            }

            if (rnd.Next(8) == 0)
            {
                comment = rnd.Next(2) == 0 ? "(ROUGH 粗加工)" : "()";
            }

            // Render: optional N, words with random glue, F somewhere, comment somewhere.
            sb.Append(prefix);
            if (rnd.Next(3) == 0)
            {
                sb.Append('N').Append(line).Append(' ');
            }

            var feedAt = feed == null ? -1 : rnd.Next(tokens.Count + 1);
            for (var i = 0; i <= tokens.Count; i++)
            {
                if (i == feedAt)
                {
                    sb.Append('F').Append(feed).Append(rnd.Next(2) == 0 ? " " : "");
                }

                if (i == tokens.Count)
                {
                    break;
                }

                var (l, n) = tokens[i];
                var letter = rnd.Next(15) == 0 ? char.ToLowerInvariant(l) : l;
                sb.Append(letter).Append(rnd.Next(10) == 0 ? "  " : "").Append(n).Append(rnd.Next(3) == 0 ? "" : " ");
                if (i == 0 && comment.Length > 0)
                {
                    sb.Append(comment);
                }
            }

            if (tokens.Count == 0 && comment.Length > 0)
            {
                sb.Append(comment);
            }

            if (!(prefix == "/" && blockDelete))
            {
                var words = string.Join(' ', tokens.Select(t => $"{t.L}{t.N}"));
                expected.Add(new Expected(line, words, feed, motion, dwell, ends && !motion));
            }

        EndLine:
            sb.Append(rnd.Next(3) == 0 ? "\r\n" : "\n");
        }

        if (rnd.Next(2) == 0)
        {
            // The closing tape mark, and text after it that is not program.
            sb.Append("%\n").Append(rnd.Next(2) == 0 ? "G01 X999 (after the tape end: ignored)\n" : "");
        }

        return (Encoding.UTF8.GetBytes(sb.ToString()), expected);
    }

    [Theory]
    [InlineData(1)]
    [InlineData(2)]
    [InlineData(3)]
    [InlineData(4)]
    [InlineData(5)]
    [InlineData(6)]
    [InlineData(7)]
    [InlineData(8)]
    public void Random_programs_round_trip_within_both_limits(int seed)
    {
        var rnd = new Random(seed);
        for (var round = 0; round < 12; round++)
        {
            var blockDelete = rnd.Next(4) != 0;
            var (bytes, expected) = Generate(rnd, rnd.Next(1, 600), blockDelete);
            if (expected.Count == 0)
            {
                continue;
            }

            var options = new SplitOptions
            {
                BlocksPerChunk = rnd.Next(1, 120),
                RotWords = rnd.Next(40, 900),
                WordsPerBlock = rnd.Next(1, 8),
                BytesPerWord = rnd.Next(6, 12),
                Tracking = rnd.Next(2) == 0 ? TrackingPlacement.Exact : TrackingPlacement.Paper,
                Feed = rnd.Next(2) == 0 ? FeedMode.Paper : FeedMode.Override,
                TrackVariable = rnd.Next(2) == 0 ? "M0" : "M1000",
                FeedVariable = rnd.Next(2) == 0 ? "P500" : "Q77",
                BlockDelete = blockDelete,
                ProgramTail = rnd.Next(3) switch { 0 => "M05", 1 => "M03 M05", _ => "" },
            };
            using var tp = new TempProgram(bytes);
            var r = tp.Split(options);
            Check(r, options, expected, bytes, $"seed {seed} round {round}");
        }
    }

    private static void Check(SplitResult r, SplitOptions o, List<Expected> written, byte[] source, string because)
    {
        var expected = o.Feed == FeedMode.Paper ? WithFeedChangesOnly(written) : written;
        var m = r.Manifest;
        m.SourceSha256.Should().Be(Convert.ToHexStringLower(System.Security.Cryptography.SHA256.HashData(source)), because);
        m.SourceSize.Should().Be(source.Length);
        m.TotalBlocks.Should().Be(expected.Count, because);
        m.TotalMotionBlocks.Should().Be(expected.Count(e => e.Motion || e.Dwell), because);
        m.Chunks.Sum(c => c.BlockCount).Should().Be(m.TotalBlocks);
        m.Chunks.Select(c => c.Index).Should().Equal(Enumerable.Range(1, m.Chunks.Count));
        ChunkManifest.Load(r.ManifestPath).Should().BeEquivalentTo(m, because);

        // Limits and file integrity.
        var blockIndex = 0;
        foreach (var c in m.Chunks)
        {
            var path = Path.Combine(r.OutputDirectory, c.FileName);
            var fileBytes = File.ReadAllBytes(path);
            fileBytes.Length.Should().Be((int)c.ByteSize);
            fileBytes.Length.Should().BeLessThanOrEqualTo((int)o.MaxChunkBytes, because);
            fileBytes.Should().OnlyContain(b => b < 128 && (b >= 32 || b == '\r' || b == '\n'), because);
            ChunkText.Sha(path).Should().Be(c.Sha256);
            c.BlockCount.Should().BeInRange(1, o.BlocksPerChunk, because);
            c.EstimatedWords.Should().BeLessThanOrEqualTo(o.RotWords, because);
            var mine = expected.Skip(blockIndex).Take(c.BlockCount).ToList();
            c.FirstSourceLine.Should().Be(mine[0].Line, because);
            c.LastSourceLine.Should().Be(mine[^1].Line, because);
            c.MotionBlockCount.Should().Be(mine.Count(e => e.Motion || e.Dwell), because);
            m.ChunkOfLine(mine[^1].Line).Should().Be(c);
            blockIndex += c.BlockCount;
        }

        // Strip the annotations: the source blocks come back exactly once and in order.
        var body = ChunkText.Body(r, o);
        var track = o.TrackVariable + "==";
        var units = new List<string>();
        foreach (var line in body)
        {
            if (o.Feed == FeedMode.Paper && line.StartsWith(o.FeedVariable + "=", StringComparison.Ordinal))
            {
                units.Add("F:" + line[(o.FeedVariable.Length + 1)..]);
                continue;
            }

            var tokens = line.Split(' ').ToList();
            var markers = tokens.Select((t, i) => (t, i)).Where(x => x.t.StartsWith(track, StringComparison.Ordinal)).ToList();
            markers.Count.Should().BeLessThanOrEqualTo(1, because);
            string marker = "";
            if (markers.Count == 1)
            {
                var expectAt = o.Tracking == TrackingPlacement.Exact ? 0 : tokens.Count - 1;
                markers[0].i.Should().Be(expectAt, $"{because}: marker placement in '{line}'");
                marker = "@" + markers[0].t[track.Length..];
                tokens.RemoveAt(markers[0].i);
            }

            var feedExpr = $"F({o.FeedVariable})";
            var hadFeedExpr = tokens.Remove(feedExpr);
            tokens.Should().NotContain(feedExpr);
            units.Add("W:" + string.Join(' ', tokens) + marker + (hadFeedExpr ? "+F" : ""));
        }

        var want = new List<string>();
        foreach (var e in expected)
        {
            var words = e.Words;
            if (e.Feed != null)
            {
                if (o.Feed == FeedMode.Paper)
                {
                    want.Add("F:" + e.Feed);
                }
                else
                {
                    // Override keeps F where it was written; compare as a set of tokens below by normalising order.
                    words = words.Length == 0 ? "F" + e.Feed : words + " F" + e.Feed;
                }
            }

            if (words.Length > 0)
            {
                var marker = e.Motion || e.Dwell ? "@" + e.Line : "";
                var plusF = o.Feed == FeedMode.Paper && e.Motion ? "+F" : "";
                want.Add("W:" + words + marker + plusF);
            }
        }

        if (o.Feed == FeedMode.Override)
        {
            // F keeps its source position; the oracle appended it, so compare with F moved to the end.
            units = units.Select(MoveFeedToEnd).ToList();
        }

        units.Should().Equal(want, because);
    }

    /// <summary>
    /// Paper feed mode sets the feed variable only where the programmed feed changes: an unchanged F is dropped, and a
    /// block that held nothing else produces no line at all.
    /// </summary>
    private static List<Expected> WithFeedChangesOnly(List<Expected> blocks)
    {
        var result = new List<Expected>();
        double? set = null;
        foreach (var e in blocks)
        {
            var feed = e.Feed;
            if (feed != null)
            {
                var value = double.Parse(feed, System.Globalization.CultureInfo.InvariantCulture);
                if (value == set)
                {
                    feed = null;
                }

                set = value;
            }

            if (feed != null || e.Words.Length > 0)
            {
                result.Add(e with { Feed = feed });
            }
        }

        return result;
    }

    private static string MoveFeedToEnd(string unit)
    {
        var at = unit.IndexOf('@');
        var words = at < 0 ? unit[2..] : unit[2..at];
        var rest = at < 0 ? "" : unit[at..];
        var tokens = words.Split(' ', StringSplitOptions.RemoveEmptyEntries).ToList();
        var f = tokens.FirstOrDefault(t => t.StartsWith('F'));
        if (f != null)
        {
            tokens.Remove(f);
            tokens.Add(f);
        }

        return "W:" + string.Join(' ', tokens) + rest;
    }
}
