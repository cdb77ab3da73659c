using PmacStream.GCode;

namespace PmacStream.IntegrationTests.Check;

/// <summary>`pmacstream profiles`: the built-in profiles, one profile's codes, its JSON, and docs/profiles.md. Tests share the output hook, so they run in sequence.</summary>
[Collection(nameof(ProfilesCommandTests))]
public sealed class ProfilesCommandTests
{
    private static (int Code, string Output) Run(params string[] args)
    {
        var (code, output, _) = CliRun.InProcess(["profiles", .. args]);
        return (code, output);
    }

    [Fact]
    public void Without_a_name_it_lists_the_built_in_profiles_default_first()
    {
        var (code, output) = Run();
        code.Should().Be(0);
        var names = output.Split('\n').Where(l => l.Length > 0 && !char.IsWhiteSpace(l[0]) && !l.StartsWith("pmacstream", StringComparison.Ordinal))
            .Select(l => l.Split(' ')[0]).ToList();
        names.Should().Equal(MachineProfile.BuiltInNames);
        output.Should().Contain("fanuc-mill     (default)");
    }

    [Fact]
    public void With_a_name_it_lists_each_code_its_group_meaning_and_what_runs_it()
    {
        var (code, output) = Run("grbl");
        code.Should().Be(0);
        var rows = output.Split('\n').Select(l => l.TrimEnd()).ToList();
        rows.Should().Contain(l => l.StartsWith("G0 ", StringComparison.Ordinal) && l.EndsWith("PROG 1000 N0: RAPID Q31=0", StringComparison.Ordinal));
        rows.Should().Contain(l => l.StartsWith("G10 ", StringComparison.Ordinal) && l.Contains("PROG 1000 N10000:") && l.Contains("needs L P"));
        rows.Should().Contain(l => l.StartsWith("M5 ", StringComparison.Ordinal) && l.Contains("PROG 1001 N5000: DWELL0 M902=0"));
        rows.Should().NotContain(l => l.StartsWith("M6 ", StringComparison.Ordinal), "grbl has no tool changer");
        Run("no-such-profile").Code.Should().Be(2);
    }

    [Fact]
    public void Json_is_a_profile_file_that_reads_back_as_the_same_profile()
    {
        var (code, output) = Run("linuxcnc-mill", "--json");
        code.Should().Be(0);
        var again = MachineProfile.Parse(output);
        again.GCodes.Should().BeEquivalentTo(MachineProfile.Named("linuxcnc-mill")!.GCodes);
        Run("--json").Code.Should().Be(2, "--json needs a profile");
    }

    [Fact]
    public void The_profile_table_in_docs_is_what_the_command_writes()
    {
        var (code, output) = Run("--markdown");
        code.Should().Be(0);
        var doc = Path.Combine(RepoRoot.Path, "docs", "profiles.md");
        File.ReadAllText(doc).Replace("\r\n", "\n").Should().Be(output, "docs/profiles.md is generated: pmacstream profiles --markdown > docs/profiles.md");
        foreach (var name in MachineProfile.BuiltInNames)
        {
            output.Should().Contain("## " + name);
        }
    }
}
