using PmacStream.Preparation;

namespace PmacStream.Core.Tests.Preparation;

/// <summary>The chunk writer's file creation (straight through libc on Linux).</summary>
public class NewFileTests
{
    [Fact]
    public void Writes_every_byte_and_never_replaces_a_file()
    {
        using var temp = new TestFolder("newfile");
        var folder = temp.Path;
        var data = new byte[3_000_001];
        new Random(5).NextBytes(data);
        var path = Path.Combine(folder, "a_0001.pmc");
        NewFile.Write(path, data);
        File.ReadAllBytes(path).Should().Equal(data);

        var again = () => NewFile.Write(path, new byte[] { 1, 2, 3 });
        again.Should().Throw<IOException>().WithMessage($"*{path}*");
        File.ReadAllBytes(path).Should().Equal(data, "the existing file is left as it was");

        var missing = () => NewFile.Write(Path.Combine(folder, "no-such-folder", "b.pmc"), data);
        missing.Should().Throw<IOException>();

        var empty = Path.Combine(folder, "empty.pmc");
        NewFile.Write(empty, ReadOnlySpan<byte>.Empty);
        new FileInfo(empty).Length.Should().Be(0);
    }
}
