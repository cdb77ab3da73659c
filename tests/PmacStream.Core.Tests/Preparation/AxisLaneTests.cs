using System.Text;
using PmacStream.GCode;
using PmacStream.Preparation;

namespace PmacStream.Core.Tests.Preparation;

/// <summary>
/// The splitter's fast lane (<see cref="AxisLine"/>) against the full lexer, checker and emitter: it may only change
/// speed. Each test runs both paths on the same input and compares everything they give.
/// </summary>
public class AxisLaneTests
{
    /// <summary>Work offsets that are not zero: the lane must add them as the interpreter does.</summary>
    private static readonly MachineProfile OffsetProfile = MachineProfile.Parse(MachineProfile.Default.ToJson().Replace(
        "\"workOffsets\": {}", "\"workOffsets\": { \"G54\": [1.5, -2.25, 0.125], \"G55\": [100, 50, -10] }", StringComparison.Ordinal));

    [Fact]
    public void The_offset_profile_has_offsets() => OffsetProfile.WorkOffset(54).Should().Be(new Point3(1.5, -2.25, 0.125));

    // ---- AxisLine alone ----

    [Theory]
    [InlineData("N22 X3.5000 Y0.0000 Z-1.5623", "X3.5000 Y0.0000 Z-1.5623")]
    [InlineData("G1X2.2490Y0.1258Z0.0000", "G1 X2.2490 Y0.1258 Z0.0000")]
    [InlineData("  G01\tX-.5  ", "G01 X-.5")]
    [InlineData("N7 G00 Z5.", "G00 Z5.")]
    [InlineData("X1 Y2 Z3", "X1 Y2 Z3")]
    [InlineData("Y-123456789.12345", "Y-123456789.12345")]
    public void Takes_lane_shaped_lines_with_the_lexers_values_and_the_emitted_text(string line, string text)
    {
        var a = Parse(line);
        a.Should().NotBeNull(line);
        Encoding.ASCII.GetString(a!.Value.Text).Should().Be(text);
        var lexed = GCodeReader.LexLine(line);
        lexed.LexicalDiagnostics.Should().BeEmpty();
        foreach (var w in lexed.Words)
        {
            switch (w.Letter)
            {
                case 'N': a.Value.Line.HasN.Should().BeTrue(); break;
                case 'G': a.Value.Line.G.Should().Be(w.Value); break;
                default: Bits(a.Value.Value(w.Letter)).Should().Be(Bits(w.Value), $"{w.Letter} of {line}"); break;
            }
        }

        a.Value.Line.Words.Should().Be(lexed.Words.Count(w => w.Letter != 'N'));
        a.Value.Line.Axes.Should().Be(lexed.Words.Where(w => w.Letter is 'X' or 'Y' or 'Z').Sum(w => 1 << (w.Letter - 'X')));
    }

    [Theory]
    [InlineData("")]                          // no words
    [InlineData("N10")]                       // no axis
    [InlineData("G1")]                        // no axis
    [InlineData("X+1")]                       // the PMAC reads + as an operator: the emitter drops it
    [InlineData("x1")]                        // lower case is reported
    [InlineData("X 1")]                       // blank inside a word
    [InlineData("X1.2.3")]                    // malformed
    [InlineData("X.")]                        // no digit
    [InlineData("X-")]
    [InlineData("X1 X2")]                     // duplicate word
    [InlineData("X1 N5")]                     // N not first
    [InlineData("N1.5 X1")]                   // N not an integer
    [InlineData("G2 X1")]                     // only G0/G1
    [InlineData("G1.0 X1")]
    [InlineData("G-1 X1")]
    [InlineData("G1 G0 X1")]
    [InlineData("X1 F100")]                   // F goes to P500
    [InlineData("X1 A2")]
    [InlineData("X1 (comment)")]
    [InlineData("X1 ;comment")]
    [InlineData("/X1")]
    [InlineData("%")]
    [InlineData("X1234567890123456")]         // 16 digits: the BCL parser's job
    [InlineData("X1\u000bY2")]                // a blank the lane does not take
    [InlineData("X1\0")]
    public void Leaves_everything_else_to_the_full_path(string line) =>
        Parse(line).Should().BeNull(line);

    [Fact]
    public void Says_no_without_a_line_end_or_the_slack_after_the_line()
    {
        var bytes = Encoding.ASCII.GetBytes("X1 Y2\n" + new string(' ', 16));
        var text = new byte[64];
        AxisLine.TryParse(bytes, 0, 5, text, 0, out _).Should().BeTrue();
        AxisLine.TryParse(bytes, 0, 4, text, 0, out _).Should().BeFalse("no line end after the line");
        AxisLine.TryParse(bytes.AsSpan(0, 20).ToArray(), 0, 5, text, 0, out _).Should().BeFalse("fewer than 16 bytes after it");
        AxisLine.TryParse(bytes, 0, 5, new byte[AxisLine.TextRoom(5) - 1], 0, out _).Should().BeFalse("too little text room");
    }

    [Fact]
    public void Random_numbers_get_the_lexers_values_bit_for_bit()
    {
        var rng = new Random(4242);
        for (var n = 0; n < 20000; n++)
        {
            var intDigits = rng.Next(0, 9);
            var fracDigits = rng.Next(0, 16 - intDigits);
            if (intDigits + fracDigits == 0)
            {
                intDigits = 1;
            }

            var number = (rng.Next(2) == 0 ? "-" : "") + Digits(rng, intDigits) + (fracDigits > 0 || rng.Next(3) == 0 ? "." + Digits(rng, fracDigits) : "");
            var line = $"X{number} Y{number} Z0";
            var a = Parse(line);
            a.Should().NotBeNull(line);
            var expected = GCodeReader.LexLine(line).Words[0].Value;
            Bits(a!.Value.Value('X')).Should().Be(Bits(expected), line);
            Bits(a.Value.Value('Y')).Should().Be(Bits(expected), line);
        }
    }

    [Fact]
    public void Random_short_lines_the_lane_takes_are_read_the_same_by_the_lexer()
    {
        var rng = new Random(9001);
        const string alphabet = "0123456789012345678901234567890123456789..--  \tNGXYZXYZXYZ+A(x;/\u000b";
        var taken = 0;
        for (var n = 0; n < 60000; n++)
        {
            var length = rng.Next(0, 64);
            var chars = new char[length];
            for (var i = 0; i < length; i++)
            {
                chars[i] = alphabet[rng.Next(rng.Next(4) == 0 ? alphabet.Length : 50)];
            }

            var line = new string(chars);
            if (rng.Next(3) == 0)
            {
                line = "N" + rng.Next(100000) + " G" + (rng.Next(2) == 0 ? "0" : "01") + " X" + line;
                line = line[..Math.Min(line.Length, 63)];
            }

            var parsed = Parse(line);
            if (parsed is not { } a)
            {
                continue;
            }

            taken++;
            var lexed = GCodeReader.LexLine(line);
            lexed.LexicalDiagnostics.Should().BeEmpty(line);
            var words = lexed.Words.Where(w => w.Letter != 'N').ToList();
            Encoding.ASCII.GetString(a.Text).Should().Be(string.Join(" ", words.Select(w => w.Letter + line.Substring(w.NumberStart, w.NumberLength))), line);
            foreach (var w in words.Where(w => w.Letter != 'G'))
            {
                Bits(a.Value(w.Letter)).Should().Be(Bits(w.Value), line);
            }
        }

        taken.Should().BeGreaterThan(1000, "the generator makes lane-shaped lines often enough to compare");
    }

    // ---- the reader's raw lines ----

    [Fact]
    public void Raw_lines_lex_to_the_same_blocks_as_Read_at_every_buffer_size()
    {
        var rng = new Random(77);
        var text = RandomProgram(rng, 600, clean: false);
        foreach (var bufferSize in new[] { 16, 37, 100, 4096, 1 << 16 })
        {
            using var expected = new GCodeReader(new MemoryStream(text), bufferSize: bufferSize);
            using var raw = new GCodeReader(new MemoryStream(text), bufferSize: bufferSize);
            while (true)
            {
                var more = expected.Read();
                raw.ReadRaw(out var data, out var start, out var length).Should().Be(more);
                if (!more)
                {
                    break;
                }

                var e = expected.Current;
                data.AsSpan(start, length).ToArray().Should().Equal(e.Line.ToArray());
                data[start + length].Should().BeOneOf((byte)'\n', (byte)'\r', (byte)0);
                (data.Length - start - length).Should().BeGreaterThan(GCodeReader.RawSlack);
                raw.LineNumber.Should().Be(e.LineNumber);
                var r = raw.LexRaw();
                (r.LineNumber, r.ByteOffset, r.Length, r.IsTapeMark, r.BlockDelete).Should().Be((e.LineNumber, e.ByteOffset, e.Length, e.IsTapeMark, e.BlockDelete));
                r.Words.Should().Equal(e.Words);
                r.LexicalDiagnostics.Should().Equal(e.LexicalDiagnostics);
                r.Comments.Should().Equal(e.Comments);
            }

            raw.Position.Should().Be(text.Length);
        }
    }

    /// <summary>
    /// Found by the fuzz target: a junk line that starts with a letter ("ray", no word in it) made the raw reader
    /// take it as the first block, so the next % ended its tape while Read (check) read on. Lexed lines are judged
    /// by their words on both paths.
    /// </summary>
    [Theory]
    [InlineData("1\n%\nray\n%\nG01 X1 F100\nM30\n")]
    [InlineData("ray Progr0am)\n%\nG00 X1\n%\nG00 X2\n")]
    public void A_junk_line_that_starts_with_a_letter_ends_the_tape_on_neither_path(string program)
    {
        var text = Encoding.ASCII.GetBytes(program);
        using var read = new GCodeReader(new MemoryStream(text));
        using var raw = new GCodeReader(new MemoryStream(text));
        var lines = 0;
        while (read.Read())
        {
            raw.ReadRaw(out _, out _, out _).Should().BeTrue($"line {read.Current.LineNumber} is read by Read too");
            raw.LexRaw().Words.Should().Equal(read.Current.Words);
            lines++;
        }

        raw.ReadRaw(out _, out _, out _).Should().BeFalse();
        (raw.TapeEndLine, raw.LineNumber).Should().Be((read.TapeEndLine, read.LineNumber));
        lines.Should().BeGreaterThanOrEqualTo(4);
    }

    // ---- the checker ----

    [Theory]
    [InlineData(1, true)]
    [InlineData(2, true)]
    [InlineData(3, false)]
    [InlineData(4, false)]
    [InlineData(5, true)]
    public void The_checker_gives_the_same_findings_totals_and_position_through_the_lane(int seed, bool clean)
    {
        var rng = new Random(seed);
        var taken = 0;
        for (var round = 0; round < 20; round++)
        {
            var text = RandomProgram(rng, rng.Next(50, 400), clean);
            taken += CheckSameThroughTheLane(text, round % 2 == 0 ? MachineProfile.Default : OffsetProfile, $"seed {seed} round {round}");
        }

        // Inch mode closes the lane too (its values are converted to millimetres on the full path).
        taken.Should().BeGreaterThan(250, "both paths are exercised: the lane for hundreds of lines, between mode changes that close it");
    }

    // ---- the splitter ----

    public static TheoryData<int, bool, TrackingPlacement, FeedMode> SplitCases()
    {
        var data = new TheoryData<int, bool, TrackingPlacement, FeedMode>();
        var seed = 100;
        foreach (var check in new[] { true, false })
        {
            foreach (var tracking in new[] { TrackingPlacement.Exact, TrackingPlacement.Paper })
            {
                foreach (var feed in new[] { FeedMode.Paper, FeedMode.Override })
                {
                    data.Add(seed++, check, tracking, feed);
                }
            }
        }

        return data;
    }

    [Theory]
    [MemberData(nameof(SplitCases))]
    public void Random_programs_split_the_same_through_the_lane(int seed, bool check, TrackingPlacement tracking, FeedMode feed)
    {
        var rng = new Random(seed);
        for (var round = 0; round < 12; round++)
        {
            var text = RandomProgram(rng, rng.Next(100, 1500), clean: round % 3 != 0);
            var options = new SplitOptions
            {
                CheckProfile = check ? (round % 2 == 0 ? MachineProfile.Default : OffsetProfile) : null,
                AllowErrors = !check,
                Tracking = tracking,
                Feed = feed,
                BlocksPerChunk = rng.Next(5, 200),
            };
            SameSplit(text, options, $"seed {seed} round {round}");
        }
    }

    [SkippableFact]
    public void Corpus_programs_split_the_same_through_the_lane()
    {
        var files = Requires.Corpus();
        files.Should().HaveCountGreaterThan(10);
        foreach (var file in files)
        {
            var bytes = File.ReadAllBytes(file);
            SameSplit(bytes, new SplitOptions { CheckProfile = MachineProfile.Default }, file);
            SameSplit(bytes, new SplitOptions { AllowErrors = true, BlocksPerChunk = 333 }, file);
        }
    }

    [Fact]
    public void A_generated_surfacing_program_goes_almost_wholly_through_the_lane_and_splits_the_same()
    {
        // Blocks N6 to N4999 of the kit's surfacing pass.
        var sb = new StringBuilder(TestPrograms.Text("%\nO0001 (SURFACING)\nN1 G21 G17 G90 G54\nN2 T1\nN3 S8000 M03\nN4 G00 Z5.0\nN5 G01 Z-1.0 F1500.\n", 4994, n => TestPrograms.Surfacing(n + 5),
            "N5000 M05\nN5001 M30\n%\n"));
        var bytes = Encoding.ASCII.GetBytes(sb.ToString());
        SameSplit(bytes, new SplitOptions { CheckProfile = MachineProfile.Default }, "surfacing", mustSplit: true);
        // Many read buffers' worth: nearly all lines are scanned in place, only those across two reads are not.
        var longer = new StringBuilder(sb.ToString()[..sb.ToString().IndexOf("N5000 M05", StringComparison.Ordinal)]);
        for (var i = 5000; i < 99_000; i++)
        {
            longer.Append(TestPrograms.Surfacing(i)).Append('\n');
        }

        longer.Append("N99000 M30\n");
        var many = Encoding.ASCII.GetBytes(longer.ToString());
        using var big = new TempProgram(many);
        var r = big.Split(new SplitOptions { CheckProfile = MachineProfile.Default });
        r.LaneLines.Should().Be(98_995, "every line from N4 to N98999 but N5");
        r.BufferLaneLines.Should().BeGreaterThan(r.LaneLines - 200, $"{many.Length} bytes are only {many.Length >> 16} read buffers");

        var lines = new List<string>();
        var check = new CheckRun(MachineProfile.Default, false, _ => { }, null, null);
        using var reader = new GCodeReader(new MemoryStream(bytes));
        var room = new byte[4096];
        var taken = 0;
        while (reader.ReadRaw(out var data, out var start, out var length))
        {
            if (AxisLine.TryParse(data, start, length, room, 0, out var line) && check.TryAxisLine(reader.LineNumber, line, room, 0))
            {
                taken++;
            }
            else
            {
                check.Line(reader.LexRaw());
            }
        }

        taken.Should().Be(4995, "every N X Y Z line in G01 with a feed, and N4's G00 Z5.0 (G00 is the power-on mode)");
    }

    /// <summary>
    /// Checks <paramref name="text"/> through the full path and through the lane, as the splitter reads it: the same
    /// findings, totals, position after every line and modal state. Returns how many lines the lane took.
    /// </summary>
    internal static int CheckSameThroughTheLane(byte[] text, MachineProfile profile, string because)
    {
        var taken = 0;
        var expected = new List<Diagnostic>();
        var reference = new CheckRun(profile, measureMoves: false, expected.Add, null, null);
        var got = new List<Diagnostic>();
        var laned = new CheckRun(profile, measureMoves: false, got.Add, null, null);
        using (var a = new GCodeReader(new MemoryStream(text), bufferSize: 256))
        using (var b = new GCodeReader(new MemoryStream(text), bufferSize: 256))
        {
            var textRoom = new byte[1 << 20];
            while (a.Read())
            {
                b.ReadRaw(out var data, out var start, out var length).Should().BeTrue(because);
                reference.Line(a.Current);
                if (AxisLine.TryParse(data, start, length, textRoom, 0, out var line) && laned.TryAxisLine(b.LineNumber, line, textRoom, 0))
                {
                    taken++;
                }
                else
                {
                    laned.Line(b.LexRaw());
                }

                laned.Interpreter.Position.Should().Be(reference.Interpreter.Position, $"after line {a.Current.LineNumber} ({because})");
            }

            b.ReadRaw(out _, out _, out _).Should().BeFalse(because);
            var s1 = reference.Finish("p", a.Position, TimeSpan.Zero);
            var s2 = laned.Finish("p", b.Position, TimeSpan.Zero);
            s2.ToString().Should().Be(s1.ToString(), because);
            s2.Lines.Should().Be(s1.Lines, because);
            s2.Blocks.Should().Be(s1.Blocks, because);
            s2.Bytes.Should().Be(s1.Bytes, because);
            s2.EstimatedSeconds.Should().Be(s1.EstimatedSeconds, because);
        }

        got.Should().Equal(expected, because);
        laned.Interpreter.State.Should().Be(reference.Interpreter.State, because);
        return taken;
    }

    /// <summary>Splits <paramref name="text"/> through the lane and without it: the same refusal, or the same chunks byte for byte.</summary>
    internal static void SameSplit(byte[] text, SplitOptions options, string because, bool mustSplit = false)
    {
        using var lane = new TempProgram(text);
        using var full = new TempProgram(text);
        var (r1, e1) = Run(lane, options);
        var (r2, e2) = Run(full, options with { AxisLane = false });
        if (mustSplit)
        {
            e2.Should().BeNull(because);
        }

        if (e2 != null)
        {
            e1.Should().NotBeNull(because);
            e1!.Message.Replace(lane.Folder, "").Should().Be(e2.Message.Replace(full.Folder, ""), because);
            e1.ErrorCount.Should().Be(e2.ErrorCount, because);
            string.Join("\n", e1.Diagnostics).Should().Be(string.Join("\n", e2.Diagnostics), because);
            return;
        }

        e1.Should().BeNull(because);
        r1!.Warnings.Should().Be(r2!.Warnings, because);
        var m1 = r1.Manifest;
        var m2 = r2.Manifest;
        (m1.TotalBlocks, m1.TotalMotionBlocks, m1.SourceSha256, m1.SourceSize).Should().Be((m2.TotalBlocks, m2.TotalMotionBlocks, m2.SourceSha256, m2.SourceSize), because);
        m1.Chunks.Should().Equal(m2.Chunks, because);
        foreach (var c in m1.Chunks)
        {
            File.ReadAllBytes(Path.Combine(r1.OutputDirectory, c.FileName)).Should().Equal(File.ReadAllBytes(Path.Combine(r2.OutputDirectory, c.FileName)), because);
        }
    }

    private static (SplitResult? Result, SplitException? Error) Run(TempProgram tp, SplitOptions options)
    {
        try
        {
            return (tp.Split(options), null);
        }
        catch (SplitException e)
        {
            return (null, e);
        }
    }

    private static long Bits(double d) => BitConverter.DoubleToInt64Bits(d);

    private static Parsed? Parse(string line)
    {
        var bytes = new byte[line.Length + 80];
        Encoding.Latin1.GetBytes(line, bytes);
        bytes[line.Length] = (byte)'\n';
        var text = new byte[AxisLine.TextRoom(line.Length)];
        return AxisLine.TryParse(bytes, 0, line.Length, text, 0, out var a) ? new Parsed(a, text.AsSpan(0, a.TextLength).ToArray(), text) : null;
    }

    private readonly record struct Parsed(AxisLine Line, byte[] Text, byte[] Room)
    {
        public double Value(char axis)
        {
            var i = axis - 'X';
            return AxisLine.Value(Room.AsSpan(Line.At[i], Line.Size[i]));
        }
    }

    private static string Digits(Random rng, int count)
    {
        var c = new char[count];
        for (var i = 0; i < count; i++)
        {
            c[i] = (char)('0' + rng.Next(10));
        }

        return new string(c);
    }

    /// <summary>
    /// A program mixing lane-shaped lines (in every spacing) with everything that must leave the lane: mode and plane
    /// changes, incremental moves, work offsets, arcs (their checks read the position the lane keeps), feeds, dwells,
    /// non-modal codes, comments, block delete, and (unless clean) lexical junk; line ends mixed; sometimes a long line.
    /// </summary>
    internal static byte[] RandomProgram(Random rng, int lines, bool clean)
    {
        var sb = new StringBuilder();
        if (rng.Next(4) == 0)
        {
            sb.Append('%').Append(End(rng));
        }

        if (rng.Next(3) != 0)
        {
            sb.Append("O1234").Append(End(rng));
        }

        if (rng.Next(3) != 0)
        {
            sb.Append("G90 G54 G01 F").Append(rng.Next(1, 3000)).Append(End(rng));
        }

        var numbered = rng.Next(3) != 0;
        var n = 1;
        for (var i = 0; i < lines; i++)
        {
            var prefix = numbered && rng.Next(20) != 0 ? $"N{n++}" + Blank(rng) : "";
            string body;
            var kind = rng.Next(112);
            if (kind < 55)
            {
                body = AxisWords(rng);
            }
            else if (kind < 62)
            {
                body = (rng.Next(2) == 0 ? "G0" : "G01") + Sep(rng) + AxisWords(rng);
            }
            else
            {
                body = (kind - 62) switch
                {
                    0 => "G90",
                    1 => "G91",
                    2 => "G54",
                    3 => "G55 X1",
                    4 => "G17",
                    5 => "G18",
                    6 => $"G02 X{Num(rng)} Y{Num(rng)} I{Num(rng)} J{Num(rng)}",
                    7 => $"G03 X{Num(rng)} Y{Num(rng)} R{Num(rng)}",
                    8 => $"G01 X{Num(rng)} F{rng.Next(0, 3000)}",
                    9 => $"F{rng.Next(0, 3000)}.",
                    10 => "G04 P500",
                    11 => "G28 X0 Y0",
                    12 => "M03 S8000",
                    13 => "M05",
                    14 => "G00",
                    15 => "G01",
                    16 => "G02",
                    17 => $"X{Num(rng)} (AXIS 坐标)",
                    18 => $"X{Num(rng)} ; comment",
                    19 => "(only a comment)",
                    20 => "",
                    21 => $"/X{Num(rng)}",
                    22 => $"G01 X{Num(rng)} A{Num(rng)}",
                    23 => $"X+{Num(rng).TrimStart('-')}",
                    24 => $"X {Num(rng)}",
                    25 => $"X{Num(rng)} X{Num(rng)}",
                    26 => "G20",
                    27 => "G21",
                    28 => $"G53 Z0",
                    29 => $"X1234567890.1234567 Y1",
                    30 => $"G2 X{Num(rng)} Y{Num(rng)} R0.001",
                    31 => "G01 Z-1 F0",
                    32 => $"Y{Num(rng)}\t",
                    33 when !clean => $"x{Num(rng)}",
                    34 when !clean => $"X{Num(rng)}.5.5",
                    35 when !clean => $"X{Num(rng)}#",
                    36 when !clean => $"G05 X1",
                    37 when !clean => $"Q5 X1",
                    38 when !clean => "X1\0",
                    39 => "X" + new string('1', 3) + "." + new string('0', rng.Next(0, 2) == 0 ? 4 : 200),
                    // Cycles and offsets close the lane while they are in force and change where its values land.
                    40 => $"G81 X{Num(rng)} Y{Num(rng)} Z-1 R1 F100{End(rng)}X{Num(rng)}{End(rng)}G80",
                    41 => "G80",
                    42 => $"G98 G83 X{Num(rng)} Y{Num(rng)} Z-2 R1 Q0.5 F80{End(rng)}G80",
                    43 => "G92 X0 Y0",
                    44 => $"G10 L2 P2 X{Num(rng)} Y1",
                    45 => $"G52 X{Num(rng)}",
                    46 => "N7 (LABEL)",
                    47 => $"G28 G91 Z0{End(rng)}G90",
                    48 => $"G00 X{Num(rng)} A{Num(rng)}",
                    49 => $"G93 G01 X1 F10{End(rng)}G94",
                    50 => "G94",
                    _ => AxisWords(rng),
                };
            }

            sb.Append(prefix).Append(body).Append(End(rng));
            if (rng.Next(500) == 0)
            {
                sb.Append("X1 (").Append('c', 70_000).Append(')').Append(End(rng));
            }
        }

        sb.Append(numbered ? $"N{n} M30" : "M30");
        if (rng.Next(2) == 0)
        {
            sb.Append(End(rng));
        }

        return Encoding.UTF8.GetBytes(sb.ToString());
    }

    private static string AxisWords(Random rng)
    {
        var axes = new[] { "X", "Y", "Z" }.Where(_ => rng.Next(3) != 0).ToList();
        if (axes.Count == 0)
        {
            axes.Add("Z");
        }

        if (rng.Next(2) == 0)
        {
            axes.Reverse();
        }

        return Blank(rng, lead: true) + string.Join("", axes.Select((a, i) => (i > 0 ? Sep(rng) : "") + a + Num(rng))) + Blank(rng, lead: true);
    }

    private static string Num(Random rng) => rng.Next(8) switch
    {
        0 => rng.Next(-500, 500).ToString(System.Globalization.CultureInfo.InvariantCulture),
        1 => "." + rng.Next(0, 99999).ToString("D5", System.Globalization.CultureInfo.InvariantCulture),
        2 => "-." + rng.Next(0, 9999),
        3 => rng.Next(0, 500) + ".",
        _ => (rng.NextDouble() * 1000 - 500).ToString("0.0000", System.Globalization.CultureInfo.InvariantCulture),
    };

    private static string Sep(Random rng) => rng.Next(6) switch
    {
        0 => "",
        1 => "  ",
        2 => "\t",
        _ => " ",
    };

    private static string Blank(Random rng, bool lead = false) => rng.Next(lead ? 8 : 4) switch
    {
        0 => "",
        1 when lead => " \t",
        _ => lead ? "" : " ",
    };

    private static string End(Random rng) => rng.Next(10) switch
    {
        0 => "\r",
        1 or 2 => "\r\n",
        _ => "\n",
    };
}
