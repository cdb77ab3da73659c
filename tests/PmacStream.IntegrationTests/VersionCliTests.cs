using System.Diagnostics;
using System.Reflection;
using System.Text.RegularExpressions;
using PmacStream.IntegrationTests.Streaming;

namespace PmacStream.IntegrationTests;

/// <summary>`pmacstream --version`: the product version and the commit the build came from.</summary>
public class VersionCliTests
{
    [Fact]
    public void Version_prints_the_product_version_and_the_build_commit()
    {
        var (code, stdout, stderr) = CliProcess.Run("--version");

        code.Should().Be(0, stderr);
        var match = Regex.Match(stdout.Trim(), @"^pmacstream (\d+\.\d+\.\d+\S*) \(commit ([0-9a-f]{40}|unknown: built without git), \.NET \d+\.\d+\.\d+, [a-z0-9-]+\)$");
        match.Success.Should().BeTrue($"'{stdout.Trim()}' names the version, the commit and the runtime");
        var informational = typeof(PmacStream.Cli.CliGlobals).Assembly.GetCustomAttribute<AssemblyInformationalVersionAttribute>()!.InformationalVersion;
        match.Groups[1].Value.Should().Be(informational.Split('+')[0], "the version is the assembly's");
        if (GitHead() is { } head)
        {
            // Built from a git checkout: the commit is a real one (the build's, which may be older than HEAD while
            // developing, so only its form and its existence are checked).
            match.Groups[2].Value.Should().MatchRegex("^[0-9a-f]{40}$", "the build came from git");
            Git("cat-file", "-t", match.Groups[2].Value).Should().Be("commit", $"the commit exists (HEAD is {head})");
        }
    }

    private static string? GitHead()
    {
        try
        {
            var head = Git("rev-parse", "HEAD");
            return head.Length == 40 ? head : null;
        }
        catch (System.ComponentModel.Win32Exception)
        {
            return null; // no git on this machine
        }
    }

    private static string Git(params string[] args)
    {
        var psi = new ProcessStartInfo("git") { RedirectStandardOutput = true, RedirectStandardError = true, WorkingDirectory = AppContext.BaseDirectory };
        foreach (var a in args)
        {
            psi.ArgumentList.Add(a);
        }

        using var p = Process.Start(psi)!;
        var output = p.StandardOutput.ReadToEnd().Trim();
        p.WaitForExit();
        return p.ExitCode == 0 ? output : string.Empty;
    }
}
