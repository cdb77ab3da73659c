using PmacStream.GCode;
using PmacStream.Jobs;
using PmacStream.Pmac;
using PmacStream.Preparation;
using PmacStream.Sim;

namespace PmacStream.Core.Tests.Preparation;

/// <summary>The library records which it is; a job refuses a controller with no library or another one (issue 17).</summary>
public class LibraryIdentityTests
{
    [Fact]
    public void The_identity_is_a_profile_id_and_a_24_bit_hash_that_comments_do_not_change()
    {
        var ids = MachineProfile.BuiltInNames.Select(n => ControllerLibrary.ExpectedIdentity(MachineProfile.Named(n))).ToList();
        ids.Select(i => i.ProfileId).Should().Equal(1, 2, 3, 4);
        ids.Should().OnlyContain(i => i.Hash > 0 && i.Hash < (1 << 24));
        ids.Select(i => i.Hash).Should().OnlyHaveUniqueItems();
        Prog1000Library.IdentityOf(MachineProfile.Default, new Prog1000Options { Comments = true })
            .Should().Be(ControllerLibrary.ExpectedIdentity(), "the downloaded library has no comments and is the same library");
        Prog1000Library.IdentityOf(MachineProfile.Default, new Prog1000Options { ProgramStops = false })
            .Should().NotBe(ControllerLibrary.ExpectedIdentity(), "other routines are another library");
    }

    [Fact]
    public async Task A_controller_without_the_library_or_with_another_is_refused_unless_forced_or_loaded()
    {
        using var sim = new PmacSimulator();
        await using var link = new InProcessConnection(sim.OpenPort("host"), "sim");
        var none = () => ControllerLibrary.EnsureAsync(link, MachineProfile.Default, LibraryPolicy.Verify);
        (await none.Should().ThrowAsync<JobException>()).Which.Message.Should().Contain("no PmacStream library").And.Contain("--load-library");
        await ControllerLibrary.EnsureAsync(link, MachineProfile.Default, LibraryPolicy.Force);

        await link.DownloadAsync(ControllerLibrary.Lines(MachineProfile.Named("grbl")));
        var other = () => ControllerLibrary.EnsureAsync(link, MachineProfile.Default, LibraryPolicy.Verify);
        (await other.Should().ThrowAsync<JobException>()).Which.Message.Should().Contain("another one").And.Contain("P7000=3");

        await ControllerLibrary.EnsureAsync(link, MachineProfile.Default, LibraryPolicy.Load);
        await ControllerLibrary.EnsureAsync(link, MachineProfile.Default, LibraryPolicy.Verify);
        (await ControllerLibrary.ReadIdentityAsync(link)).Should().Be(ControllerLibrary.ExpectedIdentity());
    }

    [Fact]
    public async Task A_buffer_a_killed_host_left_open_on_the_port_does_not_hide_the_library()
    {
        using var sim = new PmacSimulator();
        await using var link = new InProcessConnection(sim.OpenPort("host"), "sim");
        await link.DownloadAsync(ControllerLibrary.Lines());

        // The killed host was downloading a chunk: its rotary buffer is still open on this port.
        await link.GetResponseAsync("OPEN ROT");
        (await ControllerLibrary.ReadIdentityAsync(link)).Should().Be((0, 0), "an open buffer stores the query as a program line");
        await link.GetResponseAsync("CLOSE");
        await link.GetResponseAsync("OPEN ROT");

        await ControllerLibrary.EnsureAsync(link, MachineProfile.Default, LibraryPolicy.Verify);
        (await ControllerLibrary.ReadIdentityAsync(link)).Should().Be(ControllerLibrary.ExpectedIdentity());
    }
}
