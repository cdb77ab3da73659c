using System.Text;
using PmacStream.Hmi;

namespace PmacStream.Core.Tests.Hmi;

public sealed class ProgramLineSourceTests : IDisposable
{
    private readonly TestFolder _temp = new("hmi");

    public void Dispose() => _temp.Dispose();

    private string Write(string name, byte[] bytes)
    {
        var path = Path.Combine(_temp.Path, name);
        File.WriteAllBytes(path, bytes);
        return path;
    }

    private static async Task<ProgramLineSource> Indexed(string path, int maxCheckpoints = ProgramLineSource.MaxCheckpoints, int stride = 16)
    {
        var s = ProgramLineSource.Open(path, maxCheckpoints, stride);
        await s.Completion;
        return s;
    }

    [Theory]
    [InlineData("", new string[0])]
    [InlineData("G0 X1", new[] { "G0 X1" })]
    [InlineData("G0 X1\n", new[] { "G0 X1" })]
    [InlineData("a\nb\n\nc", new[] { "a", "b", "", "c" })]
    [InlineData("a\r\nb\r\n", new[] { "a", "b" })]
    [InlineData("a\rb\rc\r", new[] { "a", "b", "c" })]
    [InlineData("a\r\rb", new[] { "a", "", "b" })]
    [InlineData("\n\n", new[] { "", "" })]
    [InlineData("a\n\r\nb", new[] { "a", "", "b" })]
    public async Task Counts_and_serves_lines_like_the_gcode_reader(string text, string[] expected)
    {
        using var s = await Indexed(Write("p.nc", Encoding.ASCII.GetBytes(text)));

        s.IndexedLines.Should().Be(expected.Length);
        Enumerable.Range(1, expected.Length).Select(s.GetLine).Should().Equal(expected);
        s.Invoking(x => x.GetLine(expected.Length + 1)).Should().Throw<ArgumentOutOfRangeException>();
    }

    [Fact]
    public async Task Line_numbers_agree_with_the_gcode_reader_on_mixed_line_ends()
    {
        var path = Write("mixed.nc", Encoding.ASCII.GetBytes("%\r\nO1\rG0X1\n\nG1X2Y3F100\r\n(x)\rM30"));
        using var s = await Indexed(path);
        var fromReader = PmacStream.GCode.GCodeReader.ReadAll(path).Select(b => (b.LineNumber, Text: Encoding.ASCII.GetString(b.Buffer, 0, b.Length))).ToList();

        s.IndexedLines.Should().Be(fromReader.Count);
        foreach (var (line, text) in fromReader)
        {
            s.GetLine(line).Should().Be(text, $"line {line}");
        }
    }

    [Theory]
    [InlineData(1)]
    [InlineData(7)]
    [InlineData(42)]
    public async Task Random_files_read_back_exactly_with_a_small_table_that_must_compact(int seed)
    {
        var rnd = new Random(seed);
        var ends = new[] { "\n", "\r\n", "\r" };
        var lines = new List<string>();
        var sb = new StringBuilder();
        var count = rnd.Next(3000, 9000);
        for (var i = 0; i < count; i++)
        {
            var line = rnd.Next(10) == 0 ? string.Empty : $"N{i} G1 X{rnd.Next(-999, 999)}.{rnd.Next(1000):000} Y{rnd.NextDouble():0.####}";
            lines.Add(line);
            sb.Append(line);
            // A CR end followed by an empty line ending in LF would read as one CRLF: avoid writing that pair.
            var end = ends[rnd.Next(ends.Length)];
            if (line.Length == 0 && end == "\n" && sb.Length > 0 && sb[^1] == '\r')
            {
                end = "\r";
            }

            sb.Append(end);
        }

        using var s = await Indexed(Write($"r{seed}.nc", Encoding.ASCII.GetBytes(sb.ToString())), maxCheckpoints: 8, stride: 4);

        s.IndexedLines.Should().Be(count);
        s.CheckpointCount.Should().BeLessThanOrEqualTo(8);
        s.Stride.Should().BeGreaterThan(4, "the table was full and doubled its stride");
        // Random access in random order, and a sweep, both give the written lines.
        for (var k = 0; k < 500; k++)
        {
            var n = rnd.Next(1, count + 1);
            s.GetLine(n).Should().Be(lines[n - 1], $"line {n}");
        }

        for (var n = 1; n <= count; n += 97)
        {
            s.GetLine(n).Should().Be(lines[n - 1]);
        }
    }

    [Fact]
    public async Task Index_memory_does_not_grow_with_file_size()
    {
        static byte[] Program(int lines) => Encoding.ASCII.GetBytes(TestPrograms.Text(string.Empty, lines, i => $"N{i} G1 X1.2345 Y-6.789 Z0.5", footer: string.Empty));

        using var small = await Indexed(Write("small.nc", Program(1_000)), maxCheckpoints: ProgramLineSource.MaxCheckpoints);
        using var large = await Indexed(Write("large.nc", Program(400_000)), maxCheckpoints: ProgramLineSource.MaxCheckpoints);

        large.IndexedLines.Should().Be(400_000);
        large.IndexBytes.Should().Be(small.IndexBytes).And.Be(ProgramLineSource.MaxCheckpoints * sizeof(long));
        large.CheckpointCount.Should().BeLessThanOrEqualTo(ProgramLineSource.MaxCheckpoints);
        large.GetLine(399_999).Should().Be("N399999 G1 X1.2345 Y-6.789 Z0.5");
        large.GetLine(1).Should().Be("N1 G1 X1.2345 Y-6.789 Z0.5");
    }

    [Fact]
    public async Task Chinese_comments_decode_from_utf8_and_gbk()
    {
        Encoding.RegisterProvider(CodePagesEncodingProvider.Instance);
        var gbk = Encoding.GetEncoding(936);
        var bytes = Encoding.UTF8.GetBytes("G0 X1 (粗加工)\n").Concat(gbk.GetBytes("G1 Y2 (精加工)\n")).ToArray();
        using var s = await Indexed(Write("zh.nc", bytes));

        s.GetLine(1).Should().Be("G0 X1 (粗加工)");
        s.GetLine(2).Should().Be("G1 Y2 (精加工)");
    }

    [Fact]
    public async Task A_huge_line_is_cut_for_display_and_the_next_line_is_still_found()
    {
        var huge = new string('X', 300_000);
        using var s = await Indexed(Write("huge.nc", Encoding.ASCII.GetBytes($"G0\n{huge}\nM30\n")));

        s.IndexedLines.Should().Be(3);
        s.GetLine(2).Should().HaveLength(ProgramLineSource.MaxDisplayBytes + 1).And.EndWith("…");
        s.GetLine(3).Should().Be("M30");
    }

    [Fact]
    public async Task First_lines_are_available_before_the_scan_ends()
    {
        var sb = new StringBuilder();
        for (var i = 1; i <= 200_000; i++)
        {
            sb.Append("G1 X").Append(i).Append('\n');
        }

        using var s = ProgramLineSource.Open(Write("wait.nc", Encoding.ASCII.GetBytes(sb.ToString())));
        await s.WaitForLinesAsync(100);

        s.IndexedLines.Should().BeGreaterThanOrEqualTo(100);
        s.GetLine(100).Should().Be("G1 X100");
        await s.Completion;
        s.IndexedLines.Should().Be(200_000);
    }
}
