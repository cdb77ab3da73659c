using System.Xml.Linq;

namespace PmacStream.Core.Tests.Architecture;

/// <summary>
/// The assemblies under src/ are layers along the data path (docs/architecture.md). Each project names the projects it
/// uses (src/Directory.Build.props turns transitive references off), so a reference against the direction does not
/// compile; these tests hold the allowed graph, for the project files and for the built assemblies' metadata.
/// </summary>
public sealed class LayerDirectionTests
{
    /// <summary>What each assembly may reference, and nothing else. A layer sees the layers below it on the data path.</summary>
    public static readonly IReadOnlyDictionary<string, string[]> Allowed = new Dictionary<string, string[]>
    {
        ["PmacStream.Pmac"] = [],
        ["PmacStream.Sim"] = ["PmacStream.Pmac"],
        ["PmacStream.GCode"] = [],
        ["PmacStream.Plc"] = [],
        ["PmacStream.Preparation"] = ["PmacStream.GCode"],
        ["PmacStream.Preview"] = ["PmacStream.GCode", "PmacStream.Pmac"],
        ["PmacStream.Streaming"] = ["PmacStream.Preparation", "PmacStream.GCode", "PmacStream.Pmac"],
        ["PmacStream.Core"] = ["PmacStream.Streaming", "PmacStream.Preparation", "PmacStream.GCode", "PmacStream.Pmac"],
        ["PmacStream.Hmi"] = ["PmacStream.Core", "PmacStream.GCode", "PmacStream.Preview", "PmacStream.Pmac"],
        ["PmacStream.WinForms"] = ["PmacStream.Hmi", "PmacStream.Core", "PmacStream.GCode", "PmacStream.Pmac", "PmacStream.Sim"],
        ["PmacStream.Cli"] = ["PmacStream.Core", "PmacStream.Streaming", "PmacStream.Preparation", "PmacStream.GCode", "PmacStream.Preview", "PmacStream.Plc", "PmacStream.Pmac", "PmacStream.Sim"],
    };

    public static IEnumerable<object[]> Projects() => Allowed.Keys.Select(k => new object[] { k });

    [Theory]
    [MemberData(nameof(Projects))]
    public void A_project_references_only_the_layers_below_it(string project)
    {
        Violations(project, ProjectReferences(project)).Should().BeEmpty(
            $"{project}.csproj may reference only {string.Join(", ", Allowed[project])} (docs/architecture.md)");
    }

    [Fact]
    public void Every_project_under_src_has_a_place_in_the_graph()
    {
        var projects = Directory.GetDirectories(Path.Combine(RepoRoot.Path, "src"))
            .Where(d => Directory.GetFiles(d, "*.csproj").Length > 0)
            .Select(Path.GetFileName)
            .ToList();
        projects.Should().BeEquivalentTo(Allowed.Keys, "a new assembly gets its place in the layer graph (and docs/architecture.md) first");
    }

    [Fact]
    public void Transitive_project_references_are_off_for_src()
    {
        var props = XDocument.Load(Path.Combine(RepoRoot.Path, "src", "Directory.Build.props"));
        props.Descendants("DisableTransitiveProjectReferences").Select(e => e.Value.Trim()).Should().Equal(["true"],
            "without it a project sees every project below its references and the compiler no longer holds the direction");
    }

    [Theory]
    [InlineData(typeof(global::PmacStream.GCode.Interpreter), "PmacStream.GCode")]
    [InlineData(typeof(global::PmacStream.Preparation.Splitter), "PmacStream.Preparation")]
    [InlineData(typeof(global::PmacStream.Streaming.StreamingSession), "PmacStream.Streaming")]
    [InlineData(typeof(global::PmacStream.Jobs.JobService), "PmacStream.Core")]
    [InlineData(typeof(global::PmacStream.Hmi.MainPresenter), "PmacStream.Hmi")]
    [InlineData(typeof(global::PmacStream.Preview.PreviewRenderer), "PmacStream.Preview")]
    [InlineData(typeof(global::PmacStream.Plc.PlcGenerator), "PmacStream.Plc")]
    [InlineData(typeof(global::PmacStream.Pmac.IPmacConnection), "PmacStream.Pmac")]
    public void A_built_assembly_references_only_the_layers_below_it(Type anchor, string assembly)
    {
        anchor.Assembly.GetName().Name.Should().Be(assembly);
        var used = anchor.Assembly.GetReferencedAssemblies()
            .Select(a => a.Name!)
            .Where(n => n.StartsWith("PmacStream.", StringComparison.Ordinal));
        Violations(assembly, used).Should().BeEmpty($"{assembly}.dll may use only {string.Join(", ", Allowed[assembly])}");
    }

    [Fact]
    public void A_layer_opens_its_internals_only_to_layers_above_it_and_to_tests()
    {
        var found = new List<string>();
        foreach (var (project, _) in Allowed)
        {
            foreach (var friend in Items(project, "InternalsVisibleTo").Select(i => i.Attribute("Include")!.Value))
            {
                var test = friend.EndsWith("Tests", StringComparison.Ordinal) || friend == "PmacStream.Testing";
                if (!test && !(Allowed.TryGetValue(friend, out var refs) && refs.Contains(project)))
                {
                    found.Add($"{project} -> {friend}");
                }
            }
        }

        found.Should().BeEmpty("internals open only to an assembly that may reference the layer anyway");
    }

    [Fact]
    public void The_GCode_layer_opens_its_internals_to_tests_only()
    {
        // Every layer above takes the interpreter's decisions as canonical records (ICanonicalMoves, CanonBlock) and
        // the public lexer, checker and lane API: none reads the interpreter's fields (issue 24, item 3).
        var friends = Items("PmacStream.GCode", "InternalsVisibleTo").Select(i => i.Attribute("Include")!.Value).ToList();
        friends.Should().NotBeEmpty("the GCode tests read its internals");
        friends.Should().OnlyContain(f => f.EndsWith("Tests", StringComparison.Ordinal), "GCode opens its internals to test assemblies only");
        typeof(global::PmacStream.GCode.Interpreter).Assembly.GetCustomAttributes(typeof(System.Runtime.CompilerServices.InternalsVisibleToAttribute), false)
            .Cast<System.Runtime.CompilerServices.InternalsVisibleToAttribute>()
            .Select(a => a.AssemblyName)
            .Should().OnlyContain(n => n.EndsWith("Tests", StringComparison.Ordinal), "the built GCode assembly grants what its project says");
    }

    [Fact]
    public void The_check_fails_on_a_reference_that_skips_a_layer()
    {
        // The rule itself, on references that skip or reverse a layer.
        Violations("PmacStream.Preview", ["PmacStream.Streaming"]).Should().Equal("PmacStream.Preview -> PmacStream.Streaming");
        Violations("PmacStream.GCode", ["PmacStream.Preparation"]).Should().Equal("PmacStream.GCode -> PmacStream.Preparation");
        Violations("PmacStream.Sim", ["PmacStream.Core"]).Should().Equal("PmacStream.Sim -> PmacStream.Core");
    }

    private static List<string> Violations(string project, IEnumerable<string> references) =>
        references.Where(r => !Allowed[project].Contains(r)).Select(r => $"{project} -> {r}").ToList();

    private static IEnumerable<string> ProjectReferences(string project) =>
        Items(project, "ProjectReference").Select(i => Path.GetFileNameWithoutExtension(i.Attribute("Include")!.Value.Replace('\\', '/')));

    private static IEnumerable<XElement> Items(string project, string item) =>
        XDocument.Load(Path.Combine(RepoRoot.Path, "src", project, project + ".csproj")).Descendants(item);
}
