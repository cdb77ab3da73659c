using PmacStream.Preparation;

namespace PmacStream.Core.Tests.Preparation;

/// <summary>What a killed split leaves is found by its unheld lock and removed; a live split's folder is left alone.</summary>
public class SplitWorkFolderTests
{
    [Fact]
    public void Stale_folders_go_live_and_foreign_ones_stay()
    {
        using var temp = new TestFolder("work");
        var parent = temp.Path;
        var outDir = Path.Combine(parent, "part_chunks");
        using var live = SplitWorkFolder.Create(outDir);
        File.WriteAllText(Path.Combine(live.Path, "part_0001.pmc"), "CLOSE");

        var killed = Path.Combine(parent, ".part_chunks.tmp-killed");
        Directory.CreateDirectory(killed);
        File.WriteAllText(killed + ".lock", string.Empty); // its owner died: nobody holds it
        Directory.CreateDirectory(killed + ".old");         // the old split a killed swap set aside
        var legacy = Path.Combine(parent, ".part_chunks.tmp-legacy");
        Directory.CreateDirectory(legacy);
        Directory.SetLastWriteTimeUtc(legacy, DateTime.UtcNow.AddMinutes(-5)); // no lock file, an older version's
        var young = Path.Combine(parent, ".part_chunks.tmp-young");
        Directory.CreateDirectory(young);
        var other = Path.Combine(parent, ".other_chunks.tmp-killed");
        Directory.CreateDirectory(other);

        SplitWorkFolder.RemoveStale(outDir).Should().Be(3);

        Directory.Exists(live.Path).Should().BeTrue("a running split holds its lock");
        File.Exists(Path.Combine(live.Path, "part_0001.pmc")).Should().BeTrue();
        Directory.Exists(killed).Should().BeFalse();
        File.Exists(killed + ".lock").Should().BeFalse();
        Directory.Exists(killed + ".old").Should().BeFalse();
        Directory.Exists(legacy).Should().BeFalse();
        Directory.Exists(young).Should().BeTrue("a lock-less folder is only taken once it is old");
        Directory.Exists(other).Should().BeTrue("another output folder's work is not ours");
    }

    [Fact]
    public void A_finished_split_leaves_no_work_folder_or_lock()
    {
        using var temp = new TestFolder("work");
        var parent = temp.Path;
        var src = Path.Combine(parent, "part.nc");
        File.WriteAllText(src, "G21 G90\nG00 X0 Y0\nG01 X10 F100\nM30\n");

        Splitter.Split(src);

        Directory.EnumerateFileSystemEntries(parent).Select(Path.GetFileName).Should().BeEquivalentTo(["part.nc", "part_chunks"]);
    }
}
