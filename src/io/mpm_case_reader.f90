!> Case-file reader: strict checks of the JSON case file and resolution of every default.
!>
!> Every key is read through a few typed getters (`get_real`, `get_int`, `get_vector`,
!> `get_string`, `get_choice`, `get_bool`, `get_section`) that write the messages, so a
!> missing key, a wrong type and an out-of-range value are reported the same way everywhere:
!> the key path, what was found and what is allowed. Every object is checked by `check_keys`
!> for unknown and duplicate keys before its values are read. The first error found is
!> returned (code exit_input); every message starts with the case file name.
submodule (mpm_case) mpm_case_reader
    use, intrinsic :: ieee_arithmetic, only: ieee_is_finite
    use mpm_kinds, only: i8
    use mpm_strings, only: lower, path_problem, max_name_bytes, int_text, fmt_real, fmt_below, &
        fmt_vector, fmt_box, int_list, quoted_list, plain_list, join, text_or, yes_no, same, &
        levenshtein, base_name, any_same
    use mpm_error, only: fatal_error, exit_input, exit_other
    use mpm_json, only: json_document_type, json_value_type, json_parse_file, &
        json_parse_string, json_free, json_root, json_is_valid, json_is_object, json_type_name, &
        json_get, json_size, json_item, json_key, json_number, json_string, json_bool
    use mpm_stl, only: stl_mesh_type, read_stl, check_closed
    use mpm_bodies, only: count_body_particles
    implicit none

    ! Allowed keys of each object of a case file
    character(len=*), parameter :: top_keys(*) = [character(len=10) :: "name", "dimension", &
        "domain", "particles", "materials", "bodies", "gravity", "solver", "time", "damping", &
        "contact", "output", "progress", "save_state", "load_state", "checkpoint", "guard"]
    character(len=*), parameter :: domain_keys(*) = [character(len=10) :: "nx", "ny", "nz", &
        "dx", "origin", "boundaries"]
    character(len=*), parameter :: face_keys(*) = [character(len=4) :: "xmin", "xmax", &
        "ymin", "ymax", "zmin", "zmax"]
    character(len=*), parameter :: face_object_keys(*) = [character(len=4) :: "type", "mu"]
        !! keys of a face given as an object
    character(len=*), parameter :: particle_keys(*) = [character(len=12) :: "ppc", &
        "distribution", "seed"]
    character(len=*), parameter :: elastic_keys(*) = [character(len=4) :: "name", "type", &
        "E", "nu", "rho"]
    character(len=*), parameter :: mohr_coulomb_keys(*) = [character(len=14) :: "name", &
        "type", "E", "nu", "rho", "phi", "c", "psi", "tension_cutoff", "softening", "separation"]
    character(len=*), parameter :: drucker_prager_keys(*) = [character(len=14) :: &
        mohr_coulomb_keys, "cone"]
    character(len=*), parameter :: newtonian_keys(*) = [character(len=12) :: "name", "type", &
        "rho", "viscosity", "bulk_modulus"]
    character(len=*), parameter :: any_material_keys(*) = [character(len=14) :: &
        drucker_prager_keys, "viscosity", "bulk_modulus"]
        !! keys of every material type, to tell a misplaced key from a misspelt one
    character(len=*), parameter :: softening_keys(*) = [character(len=12) :: "type", &
        "phi_residual", "c_residual", "psi_residual", "strain"]
    character(len=*), parameter :: body_keys(*) = [character(len=8) :: "name", "material", &
        "min", "max", "velocity", "file", "scale", "offset"]
    character(len=*), parameter :: body_stl_keys(*) = [character(len=6) :: "scale", "offset"]
        !! keys of a body that only apply with `file`
    character(len=*), parameter :: solver_keys(*) = [character(len=18) :: "scheme", &
        "shape_function", "locking_correction", "transfer", "flip_fraction"]
    character(len=*), parameter :: time_keys(*) = [character(len=14) :: "tend", "dt", "cfl", &
        "allow_unstable"]
    character(len=*), parameter :: damping_keys(*) = [character(len=5) :: "type", "value"]
    character(len=*), parameter :: contact_keys(*) = [character(len=6) :: "type", "mu", "file", &
        "scale", "offset"]
    character(len=*), parameter :: output_keys(*) = [character(len=16) :: "interval", "fields", &
        "grid", "directory", "overwrite", "history_interval"]
    character(len=*), parameter :: progress_keys(*) = [character(len=8) :: "interval"]
    character(len=*), parameter :: checkpoint_keys(*) = [character(len=13) :: "every_steps", &
        "every_minutes", "file", "on_signal"]
    character(len=*), parameter :: guard_keys(*) = [character(len=14) :: "energy_factor", &
        "snapshot_steps"]
    integer, parameter :: key_path_width = 80
        !! longest key path case_key_paths can list ("materials[type=...].softening.strain")

    ! Material models (codes used only inside the reader; the case stores the model name)
    integer, parameter :: model_elastic = 1, model_mohr_coulomb = 2, model_drucker_prager = 3, &
        model_newtonian = 4, model_neo_hookean = 5
    character(len=*), parameter :: model_names(5) = [character(len=14) :: "linear_elastic", &
        "mohr_coulomb", "drucker_prager", "newtonian", "neo_hookean"]
        !! name stored in material_spec_type%type for each model code
    character(len=*), parameter :: model_choices(6) = [character(len=14) :: "linear_elastic", &
        "elastic", "mohr_coulomb", "drucker_prager", "newtonian", "neo_hookean"]
        !! names accepted for materials[i].type (aliases included)
    integer, parameter :: model_choice_codes(6) = [model_elastic, model_elastic, &
        model_mohr_coulomb, model_drucker_prager, model_newtonian, model_neo_hookean]

    character(len=*), parameter :: axis_names = "xyz"
    real(wp), parameter :: degree = acos(-1.0_wp)/180.0_wp
        !! one degree [rad]: angles are given in degrees and stored in radians
    real(wp), parameter :: box_tolerance = 1.0e-9_wp
        !! tolerance of box tests, relative to dx: absorbs round-off of corners like 3*0.1
    real(wp), parameter :: max_steps = 1.0e9_wp
        !! largest number of time steps a case may need
    integer, parameter :: max_case_name = max_name_bytes - len(".xdmf.tmp")
        !! longest case name [bytes]: <name>.xdmf.tmp is a file name of the output folder
    integer, parameter :: room_written = len(".tmp")
        !! bytes added to a file the run writes (through a .tmp file and a rename)
    integer, parameter :: room_folder = 1 + max_name_bytes
        !! bytes added to the output folder: "/" and a file name
    integer, parameter :: domain_digits = 12
        !! significant digits of computed coordinates (origin + n dx) in messages

contains

    module procedure read_case_file
        type(json_document_type) :: doc
        character(len=:), allocatable :: text

        call json_parse_file(path, doc, error, text)
        if (.not. allocated(error)) then
            call resolve_case(json_root(doc), path, base_name(path), case, error)
        end if
        call json_free(doc)
        if (.not. allocated(error)) call move_alloc(text, case%text)
    end procedure read_case_file

    module procedure read_case_string
        type(json_document_type) :: doc
        character(len=:), allocatable :: src, default_name

        src = "<string>"
        default_name = "case"
        if (present(source)) then
            if (len_trim(source) > 0) then
                src = source
                default_name = base_name(source)
            end if
        end if
        call json_parse_string(text, doc, error, src)
        if (.not. allocated(error)) then
            call resolve_case(json_root(doc), src, default_name, case, error)
        end if
        call json_free(doc)
        if (.not. allocated(error)) case%text = text
    end procedure read_case_string

    module procedure case_summary
        character(len=*), parameter :: nl = new_line("a")
        character(len=:), allocatable :: line
        integer :: d, m, b, f, dim
        integer(i8) :: count, total
        logical :: viscous
        real(wp) :: extent(3), critical

        dim = case%dim
        text = ""
        text = text//"case        "//text_or(case%name, "?")//" ("//text_or(case%file, "?")//")"//nl
        if (dim == 2) then
            text = text//"dimension   2 (plane strain)"//nl
        else
            text = text//"dimension   3"//nl
        end if
        line = "grid        "//int_list(case%ncells(1:dim), " x ")//" cells, " &
            //int_list(case%ncells(1:dim) + 1, " x ")//" = "//int_text(node_count(case)) &
            //" nodes, dx = "//fmt_real(case%dx)//" m"
        text = text//line//nl
        extent(1:dim) = case%origin(1:dim) + case%ncells(1:dim)*case%dx
        text = text//"domain      "//fmt_box(case%origin(1:dim), extent(1:dim), domain_digits) &
            //" m (origin "//fmt_vector(case%origin(1:dim))//")"//nl
        line = "boundaries "
        do d = 1, dim
            line = line//" "//face_text(case, 1, d)//", "//face_text(case, 2, d)
            if (d < dim) line = line//","
        end do
        text = text//line//nl
        line = "particles   ppc = "//int_text(case%ppc)//" ("//int_text(case%ppc**dim)//" per cell), " &
            //trim(distribution_names(case%distribution))
        if (case%distribution == dist_random) line = line//", seed "//int_text(case%seed)
        text = text//line//nl
        if (allocated(case%materials)) then
            text = text//"materials   "//int_text(size(case%materials))//nl
            do m = 1, size(case%materials)
                text = text//material_text(case%materials(m))
            end do
        end if
        if (allocated(case%bodies)) then
            if (size(case%bodies) == 0) then
                text = text//"bodies      none (the particles come from load_state)"//nl
            else
                total = 0
                do b = 1, size(case%bodies)
                    total = total + body_particles(case, b)
                end do
                text = text//"bodies      "//int_text(size(case%bodies))//", "//int_text(total) &
                    //" particles"//nl
            end if
            do b = 1, size(case%bodies)
                associate (body => case%bodies(b))
                    count = body_particles(case, b)
                    line = '  "'//text_or(body%name, "?")//'"'
                    if (allocated(case%materials)) then
                        if (body%material >= 1 .and. body%material <= size(case%materials)) then
                            line = line//' material "'//case%materials(body%material)%name//'"'
                        end if
                    end if
                    text = text//line//": "//fmt_box(body%xmin(1:dim), body%xmax(1:dim)) &
                        //" m, v = "//fmt_vector(body%velocity(1:dim))//" m/s, " &
                        //int_text(count)//" particles"//nl
                end associate
            end do
        end if
        text = text//"gravity     "//fmt_vector(case%gravity(1:dim))//" m/s2"//nl
        text = text//"solver      scheme "//trim(scheme_names(case%scheme))//", shape function " &
            //trim(shape_names(case%shape))
        if (case%fbar) text = text//", F-bar locking correction"
        if (case%apic) text = text//", APIC transfer"
        if (case%flip_fraction < 1.0_wp) text = text//", velocity update " &
            //fmt_real(case%flip_fraction)//" FLIP + "//fmt_real(1.0_wp - case%flip_fraction)//" PIC"
        text = text//nl
        line = "time        tend = "//fmt_real(case%tend)//" s, "
        if (case%dt > 0.0_wp) then
            line = line//"dt = "//fmt_real(case%dt)//" s (fixed)"
        else
            line = line//"dt from CFL = "//fmt_real(case%cfl)
        end if
        if (allocated(case%materials)) then
            if (size(case%materials) > 0) then
                call case_critical_step(case, critical, viscous)
                line = line//", critical time step "//fmt_real(critical, 6)//" s at t = 0"
                if (viscous) line = line//" (viscous limit)"
            end if
        end if
        if (case%allow_unstable) line = line//", allow_unstable (no stability check)"
        text = text//line//nl
        line = "damping     "//trim(damping_names(case%damping))
        if (case%damping == damping_local) line = line//", alpha = "//fmt_real(case%damping_value)
        text = text//line//nl
        text = text//"contact     "//text_or(case%contact_type, "none")//nl
        line = "output      "//text_or(case%output_dir, "?")
        if (case%output_interval > 0.0_wp) then
            line = line//", every "//fmt_real(case%output_interval)//" s"
            if (case_step(case) > case%output_interval) line = line//" (below the time step "// &
                fmt_real(case_step(case), 6)//" s at t = 0: an output every step)"
        else
            line = line//", initial and final state only"
        end if
        line = line//", grid "//yes_no(case%output_grid)//", overwrite "//yes_no(case%overwrite)
        text = text//line//nl
        line = "fields     "
        do f = 1, nfields
            if (case%output_fields(f)) line = line//" "//trim(field_names(f))
        end do
        text = text//line//nl
        if (case%history_interval > 0.0_wp) then
            text = text//"history     every "//fmt_real(case%history_interval)//" s"//nl
        else
            text = text//"history     every time step"//nl
        end if
        text = text//"progress    every "//fmt_real(case%progress_seconds)//" s (wall clock)"//nl
        text = text//"save_state  "//text_or(case%save_state, "(none)", .true.)//nl
        text = text//"load_state  "//text_or(case%load_state, "(none)", .true.)//nl
        line = "checkpoint "
        if (case%checkpoint_steps > 0) line = line//" every "//int_text(case%checkpoint_steps)// &
            " steps,"
        if (case%checkpoint_minutes > 0.0_wp) line = line//" every "// &
            fmt_real(case%checkpoint_minutes)//" min,"
        if (case%checkpoint_on_signal) then
            line = line//" on SIGTERM/SIGINT"
        else
            line = line//" not on signals"
        end if
        line = line//", file "//text_or(case%checkpoint_file, "<output folder>/checkpoint.h5", &
            .true.)
        text = text//line//nl
        line = "guard       energy created above "//fmt_real(case%guard_energy_factor)// &
            " x the energy scale; "
        if (case%guard_snapshot_steps > 0) then
            line = line//"healthy copy every "//int_text(case%guard_snapshot_steps)//" steps"
        else
            line = line//"no healthy copy"
        end if
        text = text//line
    end procedure case_summary

    module procedure case_key_paths
        character(len=key_path_width), allocatable :: list(:)
        character(len=len(any_material_keys)), allocatable :: keys(:)
        character(len=:), allocatable :: material
        integer :: i, longest

        ! Every object the reader checks with check_keys, from the same key lists; a new
        ! section needs its line here too (the schema test then asks for its keys).
        allocate (list(0))
        call add_key_paths(list, "", top_keys)
        call add_key_paths(list, "domain", domain_keys)
        call add_key_paths(list, "domain.boundaries", face_keys)
        do i = 1, size(face_keys)
            call add_key_paths(list, "domain.boundaries."//trim(face_keys(i)), face_object_keys)
        end do
        call add_key_paths(list, "particles", particle_keys)
        do i = 1, size(model_choices)
            material = "materials[type="//trim(model_choices(i))//"]"
            keys = material_keys(model_choice_codes(i))
            call add_key_paths(list, material, keys)
            if (any_same(keys, "softening")) then
                call add_key_paths(list, material//".softening", softening_keys)
            end if
        end do
        call add_key_paths(list, "bodies[]", body_keys)
        call add_key_paths(list, "solver", solver_keys)
        call add_key_paths(list, "time", time_keys)
        call add_key_paths(list, "damping", damping_keys)
        call add_key_paths(list, "contact", contact_keys)
        call add_key_paths(list, "output", output_keys)
        call add_key_paths(list, "progress", progress_keys)
        call add_key_paths(list, "checkpoint", checkpoint_keys)
        call add_key_paths(list, "guard", guard_keys)
        longest = 0
        do i = 1, size(list)
            longest = max(longest, len_trim(list(i)))
        end do
        allocate (character(len=longest) :: paths(size(list)))
        do i = 1, size(list)
            paths(i) = list(i)
        end do
    end procedure case_key_paths

    !> Append "path.key" for every key of an object to a list of key paths.
    pure subroutine add_key_paths(list, path, keys)
        character(len=key_path_width), allocatable, intent(inout) :: list(:)
            !! key paths so far
        character(len=*), intent(in) :: path
            !! path of the object ("" at the top level)
        character(len=*), intent(in) :: keys(:)
            !! keys of the object

        integer :: k

        do k = 1, size(keys)
            list = [character(len=key_path_width) :: list, join(path, trim(keys(k)))]
        end do
    end subroutine add_key_paths

    ! ----------------------------------------------------------------------------------------
    ! Sections of the case file, in the order they are checked
    ! ----------------------------------------------------------------------------------------

    !> Check a parsed document and resolve it into `case`.
    subroutine resolve_case(root, src, default_name, case, error)
        type(json_value_type), intent(in) :: root
            !! top-level value of the document
        character(len=*), intent(in) :: src
            !! case file name, first word of every message
        character(len=*), intent(in) :: default_name
            !! case name when the file gives none
        type(case_type), intent(out) :: case
            !! resolved case
        type(error_type), allocatable, intent(out) :: error
            !! first error found

        case%file = src
        case%contact_type = "none"
        case%save_state = ""
        case%load_state = ""
        case%checkpoint_file = ""
        case%text = ""
        if (.not. json_is_object(root)) then
            call input_error(error, src, "the top level must be a JSON object { ... } holding " &
                //"the case keys, found "//describe(root))
            return
        end if
        call check_keys(root, "", top_keys, src, error)
        if (allocated(error)) return
        call read_name(root, src, default_name, case, error)
        if (allocated(error)) return
        call read_domain(root, src, case, error)
        if (allocated(error)) return
        call read_particles(root, src, case, error)
        if (allocated(error)) return
        call read_materials(root, src, case, error)
        if (allocated(error)) return
        call read_states(root, src, case, error)
        if (allocated(error)) return
        call read_bodies(root, src, case, error)
        if (allocated(error)) return
        call get_vector(root, "gravity", "", src, case%dim, case%gravity, error, unit="m/s2")
        if (allocated(error)) return
        call read_solver(root, src, case, error)
        if (allocated(error)) return
        call read_time(root, src, case, error)
        if (allocated(error)) return
        call read_damping(root, src, case, error)
        if (allocated(error)) return
        call read_contact(root, src, case, error)
        if (allocated(error)) return
        call read_output(root, src, case, error)
        if (allocated(error)) return
        call read_progress(root, src, case, error)
        if (allocated(error)) return
        call read_checkpoint(root, src, case, error)
        if (allocated(error)) return
        call read_guard(root, src, case, error)
    end subroutine resolve_case

    !> `name`: default from the file name; it becomes a folder name, so keep it simple.
    subroutine read_name(root, src, default_name, case, error)
        type(json_value_type), intent(in) :: root
            !! top-level object
        character(len=*), intent(in) :: src
            !! case file name for messages
        character(len=*), intent(in) :: default_name
            !! name used when the key is absent
        type(case_type), intent(inout) :: case
            !! case being resolved
        type(error_type), allocatable, intent(out) :: error
            !! first error found

        character(len=*), parameter :: rule = "use only letters, digits, '-', '_' and '.', " &
            //"not starting with '.' (the name is used as the output folder name)"
        logical :: found

        case%name = default_name
        call get_string(root, "name", "", src, case%name, error, found=found)
        if (allocated(error)) return
        if (len(case%name) > max_case_name) then
            if (found) then
                call input_error(error, src, 'name = "'//case%name(1:20)//'..." is '// &
                    int_text(len(case%name))//" bytes long, at most "//int_text(max_case_name) &
                    //" (it names the file <name>.xdmf.tmp of the output folder, and a file "// &
                    "name has at most "//int_text(max_name_bytes)//" bytes)")
            else
                call input_error(error, src, 'the case name "'//case%name(1:20)//'..." taken '// &
                    "from the file name is "//int_text(len(case%name))//" bytes long, at "// &
                    "most "//int_text(max_case_name)//'; set a shorter "name" in the case file')
            end if
            return
        end if
        if (valid_name(case%name)) return
        if (found) then
            call input_error(error, src, 'name = "'//case%name//'" is not allowed: '//rule)
        else
            call input_error(error, src, 'the case name "'//case%name//'" taken from the file ' &
                //"name is not allowed: "//rule//'; set "name" in the case file')
        end if
    end subroutine read_name

    !> `dimension` and `domain`: the grid.
    subroutine read_domain(root, src, case, error)
        type(json_value_type), intent(in) :: root
            !! top-level object
        character(len=*), intent(in) :: src
            !! case file name for messages
        type(case_type), intent(inout) :: case
            !! case being resolved
        type(error_type), allocatable, intent(out) :: error
            !! first error found

        type(json_value_type) :: domain
        logical :: has_nz
        integer :: d, dim
        real(wp) :: nodes

        call get_section(root, "domain", "", src, domain_keys, domain, error, required=.true.)
        if (allocated(error)) return
        has_nz = json_is_valid(json_get(domain, "nz"))
        dim = merge(3, 2, has_nz)
        call get_int(root, "dimension", "", src, dim, error, at_least=2, at_most=3)
        if (allocated(error)) return
        if (dim == 2 .and. has_nz) then
            call input_error(error, src, "domain.nz is given but dimension = 2: remove " &
                //'domain.nz for a 2D case or set "dimension": 3')
            return
        end if
        if (dim == 3 .and. .not. has_nz) then
            call input_error(error, src, "missing required key 'domain.nz' (an integer >= 1, " &
                //"cells along z): dimension = 3 needs it")
            return
        end if
        case%dim = dim
        do d = 1, dim
            call get_int(domain, "n"//axis_names(d:d), "domain", src, case%ncells(d), error, &
                required=.true., at_least=1)
            if (allocated(error)) return
        end do
        ! the grid numbers its nodes with default integers
        nodes = product(real(case%ncells(1:dim), wp) + 1.0_wp)
        if (nodes > real(huge(1), wp)) then
            call input_error(error, src, "domain: "//int_list(case%ncells(1:dim), " x ") &
                //" cells make "//fmt_real(nodes, 3)//" nodes, more than the " &
                //int_text(huge(1))//" this version can number; use fewer cells (a larger dx)")
            return
        end if
        call get_real(domain, "dx", "domain", src, case%dx, error, required=.true., &
            above=0.0_wp, unit="m")
        if (allocated(error)) return
        call get_vector(domain, "origin", "domain", src, dim, case%origin, error, unit="m")
        if (allocated(error)) return
        call read_boundaries(domain, src, case, error)
    end subroutine read_domain

    !> `domain.boundaries`: one condition per face.
    subroutine read_boundaries(domain, src, case, error)
        type(json_value_type), intent(in) :: domain
            !! the domain object
        character(len=*), intent(in) :: src
            !! case file name for messages
        type(case_type), intent(inout) :: case
            !! case being resolved (dim set)
        type(error_type), allocatable, intent(out) :: error
            !! first error found

        character(len=*), parameter :: path = "domain.boundaries"
        type(json_value_type) :: faces
        logical :: found
        integer :: k, axis, side

        call get_section(domain, "boundaries", "domain", src, face_keys, faces, error, &
            found=found)
        if (allocated(error) .or. .not. found) return
        do k = 1, size(face_keys)
            axis = (k + 1)/2
            side = 2 - mod(k, 2)
            if (axis > case%dim) then
                if (json_is_valid(json_get(faces, trim(face_keys(k))))) then
                    call input_error(error, src, path//"."//trim(face_keys(k))//" is not " &
                        //"allowed in a 2D case (dimension = 2): a 2D domain has no z faces")
                    return
                end if
                cycle
            end if
            call read_face(faces, trim(face_keys(k)), src, case%bc(side, axis), &
                case%bc_friction(side, axis), error)
            if (allocated(error)) return
        end do
    end subroutine read_boundaries

    !> One face of `domain.boundaries`: a name ("free", "sliding", "fixed") or an object
    !> {"type": ..., "mu": ...}; a frictional face is only written as an object, with its mu.
    subroutine read_face(faces, key, src, bc, mu, error)
        type(json_value_type), intent(in) :: faces
            !! the boundaries object
        character(len=*), intent(in) :: key
            !! face key ("xmin", ...)
        character(len=*), intent(in) :: src
            !! case file name for messages
        integer, intent(inout) :: bc
            !! condition of the face (unchanged when the face is not given)
        real(wp), intent(inout) :: mu
            !! Coulomb friction coefficient of a frictional face [-]
        type(error_type), allocatable, intent(out) :: error
            !! first error found

        character(len=*), parameter :: frictional_form = '{"type": "frictional", "mu": 0.4}'
        character(len=*), parameter :: allowed = 'one of "free", "sliding", "fixed", or an ' &
            //"object "//frictional_form//" for a face with Coulomb friction"
        type(json_value_type) :: val
        character(len=:), allocatable :: path, name
        integer :: i

        path = "domain.boundaries."//key
        val = json_get(faces, key)
        if (.not. json_is_valid(val)) return
        if (json_type_name(val) == "string") then
            name = json_string(val)
            do i = bc_free, bc_fixed
                if (same(lower(name), trim(bc_names(i)))) then
                    bc = i
                    return
                end if
            end do
            if (same(lower(name), trim(bc_names(bc_frictional)))) then
                call input_error(error, src, path//' = "'//name//'" needs a friction ' &
                    //"coefficient: write the face as an object, "//frictional_form)
            else
                call input_error(error, src, path//' = "'//name//'" is not allowed: must be ' &
                    //allowed)
            end if
            return
        end if
        if (json_type_name(val) /= "object") then
            call input_error(error, src, path//" has the wrong type: expected "//allowed &
                //", found "//describe(val))
            return
        end if
        call check_keys(val, path, face_object_keys, src, error)
        if (allocated(error)) return
        call get_choice(val, "type", path, src, bc_names, [bc_free, bc_sliding, bc_fixed, &
            bc_frictional], bc, error, required=.true.)
        if (allocated(error)) return
        if (bc == bc_frictional) then
            call get_real(val, "mu", path, src, mu, error, required=.true., at_least=0.0_wp)
        else if (json_is_valid(json_get(val, "mu"))) then
            call input_error(error, src, path//".mu applies to frictional faces only (here " &
                //path//'.type = "'//trim(bc_names(bc))//'"); remove mu or set "type": ' &
                //'"frictional"')
        end if
    end subroutine read_face

    !> `particles`: particles per cell and their placement.
    subroutine read_particles(root, src, case, error)
        type(json_value_type), intent(in) :: root
            !! top-level object
        character(len=*), intent(in) :: src
            !! case file name for messages
        type(case_type), intent(inout) :: case
            !! case being resolved
        type(error_type), allocatable, intent(out) :: error
            !! first error found

        type(json_value_type) :: particles
        logical :: found, has_seed
        integer :: d

        call get_section(root, "particles", "", src, particle_keys, particles, error, found=found)
        if (allocated(error) .or. .not. found) return
        call get_int(particles, "ppc", "particles", src, case%ppc, error, at_least=1, at_most=10)
        if (allocated(error)) return
        do d = 1, case%dim
            ! particle sub-cells are numbered with default integers along each axis
            if (int(case%ncells(d), i8)*case%ppc > huge(1)) then
                call input_error(error, src, "particles.ppc = "//int_text(case%ppc)//" with domain.n" &
                    //axis_names(d:d)//" = "//int_text(case%ncells(d))//" makes more than " &
                    //int_text(huge(1))//" particle positions along "//axis_names(d:d) &
                    //"; use fewer cells or a smaller ppc")
                return
            end if
        end do
        call get_choice(particles, "distribution", "particles", src, distribution_names, &
            [dist_regular, dist_random], case%distribution, error)
        if (allocated(error)) return
        has_seed = json_is_valid(json_get(particles, "seed"))
        if (has_seed .and. case%distribution /= dist_random) then
            call input_error(error, src, "particles.seed only applies to particles.distribution" &
                //' = "random"; remove it or set "distribution": "random"')
            return
        end if
        call get_int(particles, "seed", "particles", src, case%seed, error, at_least=0)
    end subroutine read_particles

    !> `materials`: a non-empty array of uniquely named materials. The keys allowed in a
    !> material depend on its type, so the type is read before the keys are checked.
    subroutine read_materials(root, src, case, error)
        type(json_value_type), intent(in) :: root
            !! top-level object
        character(len=*), intent(in) :: src
            !! case file name for messages
        type(case_type), intent(inout) :: case
            !! case being resolved
        type(error_type), allocatable, intent(out) :: error
            !! first error found

        type(json_value_type) :: list, item
        character(len=:), allocatable :: path
        integer :: i, j, model

        call get_list(root, "materials", src, "material", list, error)
        if (allocated(error)) return
        allocate (case%materials(json_size(list)))
        do i = 1, size(case%materials)
            path = "materials["//int_text(i)//"]"
            item = json_item(list, i)
            call check_type(item, path, "object", "an object", src, error)
            if (allocated(error)) return
            call read_material_type(item, path, src, model, error)
            if (allocated(error)) return
            associate (mat => case%materials(i))
                mat%type = trim(model_names(model))
                call get_string(item, "name", path, src, mat%name, error, required=.true.)
                if (allocated(error)) return
                do j = 1, i - 1
                    if (same(case%materials(j)%name, mat%name)) then
                        call input_error(error, src, path//'.name = "'//mat%name//'" is ' &
                            //"already the name of materials["//int_text(j)//"]; material names " &
                            //"must be unique")
                        return
                    end if
                end do
                if (model == model_newtonian) then
                    call read_newtonian(item, path, src, mat, error)
                    if (allocated(error)) return
                else
                    call read_elasticity(item, path, src, mat, error)
                    if (allocated(error)) return
                    if (model == model_mohr_coulomb .or. model == model_drucker_prager) then
                        call read_strength(item, path, src, model, mat, error)
                        if (allocated(error)) return
                    end if
                end if
            end associate
        end do
    end subroutine read_materials

    !> `materials[i].type`, then the keys of a material of that type.
    subroutine read_material_type(item, path, src, model, error)
        type(json_value_type), intent(in) :: item
            !! the material object
        character(len=*), intent(in) :: path
            !! its path ("materials[i]")
        character(len=*), intent(in) :: src
            !! case file name for messages
        integer, intent(out) :: model
            !! model code (model_elastic, ...)
        type(error_type), allocatable, intent(out) :: error
            !! first error found

        character(len=:), allocatable :: owner

        model = 0
        if (.not. json_is_valid(json_get(item, "type"))) then
            ! a misspelt "type" is reported as such rather than as a missing type
            call check_keys(item, path, any_material_keys, src, error)
            if (allocated(error)) return
        end if
        call get_choice(item, "type", path, src, model_choices, model_choice_codes, model, &
            error, required=.true.)
        if (allocated(error)) return
        owner = "a "//trim(model_names(model))//" material"
        call check_keys(item, path, material_keys(model), src, error, owner, any_material_keys)
    end subroutine read_material_type

    !> Keys of a material of one model (the reader's check and `case_key_paths` both use it).
    pure function material_keys(model) result(keys)
        integer, intent(in) :: model
            !! model code (model_elastic, ...)
        character(len=len(any_material_keys)), allocatable :: keys(:)

        select case (model)
        case (model_elastic, model_neo_hookean)
            keys = elastic_keys
        case (model_mohr_coulomb)
            keys = mohr_coulomb_keys
        case (model_drucker_prager)
            keys = drucker_prager_keys
        case default
            keys = newtonian_keys
        end select
    end function material_keys

    !> Elastic parameters of a solid: `E`, `nu`, `rho`.
    subroutine read_elasticity(item, path, src, mat, error)
        type(json_value_type), intent(in) :: item
            !! the material object
        character(len=*), intent(in) :: path
            !! its path ("materials[i]")
        character(len=*), intent(in) :: src
            !! case file name for messages
        type(material_spec_type), intent(inout) :: mat
            !! material being resolved
        type(error_type), allocatable, intent(out) :: error
            !! first error found

        call get_real(item, "E", path, src, mat%young, error, required=.true., above=0.0_wp, &
            unit="Pa")
        if (allocated(error)) return
        call get_real(item, "nu", path, src, mat%poisson, error, required=.true., &
            at_least=0.0_wp, below=0.5_wp)
        if (allocated(error)) return
        call get_real(item, "rho", path, src, mat%density, error, required=.true., &
            above=0.0_wp, unit="kg/m3")
    end subroutine read_elasticity

    !> Strength of a Mohr-Coulomb or Drucker-Prager material: `phi`, `c`, `psi`,
    !> `tension_cutoff`, `softening` and (Drucker-Prager) `cone`. Angles are read in degrees
    !> and stored in radians.
    subroutine read_strength(item, path, src, model, mat, error)
        type(json_value_type), intent(in) :: item
            !! the material object
        character(len=*), intent(in) :: path
            !! its path ("materials[i]")
        character(len=*), intent(in) :: src
            !! case file name for messages
        integer, intent(in) :: model
            !! model_mohr_coulomb or model_drucker_prager
        type(material_spec_type), intent(inout) :: mat
            !! material being resolved
        type(error_type), allocatable, intent(out) :: error
            !! first error found

        character(len=:), allocatable :: family, limit
        logical :: found
        real(wp) :: phi, c, psi, cutoff, apex

        family = "Mohr-Coulomb"
        if (model == model_drucker_prager) family = "Drucker-Prager"
        phi = 0.0_wp
        c = 0.0_wp
        psi = 0.0_wp
        cutoff = -1.0_wp
        call get_real(item, "phi", path, src, phi, error, required=.true., at_least=0.0_wp, &
            below=90.0_wp, unit="deg")
        if (allocated(error)) return
        call get_real(item, "c", path, src, c, error, at_least=0.0_wp, unit="Pa")
        if (allocated(error)) return
        if (phi == 0.0_wp .and. c == 0.0_wp) then
            call input_error(error, src, path//".phi = 0 and "//path//".c = 0: a "//family &
                //" material with phi = 0 and c = 0 has no strength; use a newtonian fluid, " &
                //"or give phi > 0 [deg] or c > 0 [Pa]")
            return
        end if
        call get_real(item, "psi", path, src, psi, error, at_least=0.0_wp, unit="deg")
        if (allocated(error)) return
        if (psi > phi) then
            call input_error(error, src, path//".psi = "//fmt_real(psi)//" deg is above " &
                //path//".phi = "//fmt_real(phi)//" deg: the dilatancy angle must be >= 0 " &
                //"and <= phi = "//fmt_real(phi)//" [deg]")
            return
        end if
        call get_real(item, "tension_cutoff", path, src, cutoff, error, at_least=0.0_wp, &
            unit="Pa", found=found)
        if (allocated(error)) return
        if (found .and. phi > 0.0_wp) then
            ! the cone ends at the mean stress c / tan(phi): no stress state lies beyond it
            apex = c/tan(phi*degree)
            if (cutoff > apex) then
                limit = fmt_below(apex, cutoff)
                call input_error(error, src, path//".tension_cutoff = "//fmt_real(cutoff) &
                    //" Pa is above the apex of the yield surface, c / tan(phi) = "//limit &
                    //" Pa (c = "//fmt_real(c)//" Pa, phi = "//fmt_real(phi)//" deg): must " &
                    //"be >= 0 and <= "//limit//" [Pa]")
                return
            end if
        end if
        mat%friction = phi*degree
        mat%cohesion = c
        mat%dilatancy = psi*degree
        mat%tension_cutoff = cutoff
        call get_bool(item, "separation", path, src, mat%separation, error)
        if (allocated(error)) return
        if (mat%separation .and. c > 0.0_wp .and. cutoff /= 0.0_wp) then
            call input_error(error, src, path//".separation = true needs a stress-free apex: " &
                //"c = "//fmt_real(c)//" Pa here; give c = 0 or tension_cutoff = 0, or set " &
                //"separation to false")
            return
        end if
        call read_softening(item, path, src, phi, c, psi, mat, error)
        if (allocated(error)) return
        if (model == model_drucker_prager) then
            call get_choice(item, "cone", path, src, cone_names, [cone_plane_strain, &
                cone_compression, cone_extension], mat%cone, error)
        end if
    end subroutine read_strength

    !> `materials[i].softening`: residual strength and the plastic shear strain that reaches
    !> it. Residual values default to the peak values (psi_residual to 0) and never exceed them.
    subroutine read_softening(item, path, src, phi, c, psi, mat, error)
        type(json_value_type), intent(in) :: item
            !! the material object
        character(len=*), intent(in) :: path
            !! its path ("materials[i]")
        character(len=*), intent(in) :: src
            !! case file name for messages
        real(wp), intent(in) :: phi
            !! peak friction angle [deg]
        real(wp), intent(in) :: c
            !! peak cohesion [Pa]
        real(wp), intent(in) :: psi
            !! peak dilatancy angle [deg]
        type(material_spec_type), intent(inout) :: mat
            !! material being resolved (peak values set)
        type(error_type), allocatable, intent(out) :: error
            !! first error found

        type(json_value_type) :: softening
        character(len=:), allocatable :: spath
        logical :: found
        integer :: k
        real(wp) :: phi_r, c_r, psi_r

        ! without softening the residual values are the peak values
        mat%softening = softening_none
        mat%friction_residual = mat%friction
        mat%cohesion_residual = mat%cohesion
        mat%dilatancy_residual = mat%dilatancy
        call get_section(item, "softening", path, src, softening_keys, softening, error, &
            found=found)
        if (allocated(error) .or. .not. found) return
        spath = join(path, "softening")
        call get_choice(softening, "type", spath, src, softening_names, [softening_none, &
            softening_linear, softening_exponential], mat%softening, error, required=.true.)
        if (allocated(error)) return
        if (mat%softening == softening_none) then
            do k = 2, size(softening_keys)
                if (json_is_valid(json_get(softening, trim(softening_keys(k))))) then
                    call input_error(error, src, spath//"."//trim(softening_keys(k)) &
                        //' only applies to softening.type = "linear" or "exponential" ' &
                        //'(here "none"); remove it')
                    return
                end if
            end do
            return
        end if
        phi_r = phi
        c_r = c
        psi_r = 0.0_wp
        call get_real(softening, "phi_residual", spath, src, phi_r, error, at_least=0.0_wp, &
            unit="deg")
        if (allocated(error)) return
        call check_residual(spath//".phi_residual", phi_r, path//".phi", phi, "deg", src, error)
        if (allocated(error)) return
        call get_real(softening, "c_residual", spath, src, c_r, error, at_least=0.0_wp, &
            unit="Pa")
        if (allocated(error)) return
        call check_residual(spath//".c_residual", c_r, path//".c", c, "Pa", src, error)
        if (allocated(error)) return
        call get_real(softening, "psi_residual", spath, src, psi_r, error, at_least=0.0_wp, &
            unit="deg")
        if (allocated(error)) return
        call check_residual(spath//".psi_residual", psi_r, path//".psi", psi, "deg", src, error)
        if (allocated(error)) return
        if (psi_r > phi_r) then
            call input_error(error, src, spath//".psi_residual = "//fmt_real(psi_r)//" deg " &
                //"is above the residual friction angle "//fmt_real(phi_r)//" deg: the " &
                //"dilatancy angle must be >= 0 and <= phi, also at residual strength [deg]")
            return
        end if
        if (phi_r == 0.0_wp .and. c_r == 0.0_wp) then
            call input_error(error, src, spath//": phi_residual = 0 and c_residual = 0 leave " &
                //"no strength once softened; keep phi_residual > 0 [deg] or c_residual > 0 " &
                //"[Pa] (a material without strength is a newtonian fluid)")
            return
        end if
        call get_real(softening, "strain", spath, src, mat%softening_strain, error, &
            required=.true., above=0.0_wp)
        if (allocated(error)) return
        mat%friction_residual = phi_r*degree
        mat%cohesion_residual = c_r
        mat%dilatancy_residual = psi_r*degree
    end subroutine read_softening

    !> Refuse a residual strength parameter above its peak value.
    subroutine check_residual(key, residual, peak_key, peak, unit, src, error)
        character(len=*), intent(in) :: key
            !! full key path of the residual value
        real(wp), intent(in) :: residual
            !! residual value [unit]
        character(len=*), intent(in) :: peak_key
            !! full key path of the peak value
        real(wp), intent(in) :: peak
            !! peak value [unit]
        character(len=*), intent(in) :: unit
            !! unit of both values
        character(len=*), intent(in) :: src
            !! case file name for messages
        type(error_type), allocatable, intent(out) :: error
            !! set when residual > peak

        if (residual > peak) then
            call input_error(error, src, key//" = "//fmt_real(residual)//" "//unit//" is " &
                //"above the peak value "//peak_key//" = "//fmt_real(peak)//" "//unit &
                //": residual strength above peak; must be >= 0 and <= "//fmt_real(peak) &
                //" ["//unit//"]")
        end if
    end subroutine check_residual

    !> A Newtonian fluid: `rho`, `viscosity`, `bulk_modulus`.
    subroutine read_newtonian(item, path, src, mat, error)
        type(json_value_type), intent(in) :: item
            !! the material object
        character(len=*), intent(in) :: path
            !! its path ("materials[i]")
        character(len=*), intent(in) :: src
            !! case file name for messages
        type(material_spec_type), intent(inout) :: mat
            !! material being resolved
        type(error_type), allocatable, intent(out) :: error
            !! first error found

        call get_real(item, "rho", path, src, mat%density, error, required=.true., &
            above=0.0_wp, unit="kg/m3")
        if (allocated(error)) return
        call get_real(item, "viscosity", path, src, mat%viscosity, error, required=.true., &
            at_least=0.0_wp, unit="Pa s")
        if (allocated(error)) return
        call get_real(item, "bulk_modulus", path, src, mat%bulk_modulus, error, &
            required=.true., above=0.0_wp, unit="Pa")
    end subroutine read_newtonian

    !> `save_state` and `load_state`: state files to write at the end and to start from.
    subroutine read_states(root, src, case, error)
        type(json_value_type), intent(in) :: root
            !! top-level object
        character(len=*), intent(in) :: src
            !! case file name for messages
        type(case_type), intent(inout) :: case
            !! case being resolved
        type(error_type), allocatable, intent(out) :: error
            !! first error found

        logical :: found, exists

        call get_path(root, "save_state", "", src, room_written, case%save_state, error)
        if (allocated(error)) return
        call get_path(root, "load_state", "", src, 0, case%load_state, error, found=found)
        if (allocated(error) .or. .not. found) return
        inquire (file=case%load_state, exist=exists)
        if (.not. exists) then
            call input_error(error, src, "load_state: file '"//case%load_state//"' not found " &
                //"(a relative path is taken from the current working directory)")
        end if
    end subroutine read_states

    !> `bodies`: boxes or closed STL surfaces filled with particles, inside the domain, not
    !> overlapping (bounding boxes for STL bodies), each with particles.
    subroutine read_bodies(root, src, case, error)
        type(json_value_type), intent(in) :: root
            !! top-level object
        character(len=*), intent(in) :: src
            !! case file name for messages
        type(case_type), intent(inout) :: case
            !! case being resolved (domain, particles, materials, load_state set)
        type(error_type), allocatable, intent(out) :: error
            !! first error found

        type(json_value_type) :: list, item
        character(len=:), allocatable :: path, material
        integer :: i, j
        integer(i8) :: total

        if (len(case%load_state) > 0) then
            if (json_is_valid(json_get(root, "bodies"))) then
                call input_error(error, src, "bodies cannot be given together with load_state: " &
                    //"the particles come from the state file '"//case%load_state//"'; " &
                    //"remove the bodies or remove load_state")
                return
            end if
            allocate (case%bodies(0))
            return
        end if
        if (.not. json_is_valid(json_get(root, "bodies"))) then
            call input_error(error, src, "missing required key 'bodies' (an array of boxes or " &
                //"closed STL surfaces of particles); give load_state instead to start from a " &
                //"saved state")
            return
        end if
        call get_list(root, "bodies", src, "body", list, error)
        if (allocated(error)) return
        allocate (case%bodies(json_size(list)))
        total = 0
        do i = 1, size(case%bodies)
            path = "bodies["//int_text(i)//"]"
            item = json_item(list, i)
            call check_object(item, path, body_keys, src, error)
            if (allocated(error)) return
            associate (body => case%bodies(i))
                body%name = "body"//int_text(i)
                call get_string(item, "name", path, src, body%name, error)
                if (allocated(error)) return
                do j = 1, i - 1
                    if (same(case%bodies(j)%name, body%name)) then
                        call input_error(error, src, path//'.name = "'//body%name//'" is ' &
                            //"already the name of bodies["//int_text(j)//"]; body names must " &
                            //"be unique")
                        return
                    end if
                end do
                material = ""
                call get_string(item, "material", path, src, material, error, required=.true.)
                if (allocated(error)) return
                body%material = material_index(case%materials, material)
                if (body%material == 0) then
                    call input_error(error, src, path//'.material = "'//material//'" is not a ' &
                        //"material of this case; the materials are: " &
                        //material_list(case%materials))
                    return
                end if
                if (json_is_valid(json_get(item, "file"))) then
                    call read_body_surface(item, path, src, case, body, error)
                    if (allocated(error)) return
                else
                    if (.not. (json_is_valid(json_get(item, "min")) &
                        .or. json_is_valid(json_get(item, "max")))) then
                        call input_error(error, src, path//' "'//body%name//'": give either ' &
                            //"'file' (a closed STL surface) or 'min' and 'max' (a box); " &
                            //"neither was given")
                        return
                    end if
                    do j = 1, 2
                        if (json_is_valid(json_get(item, trim(body_stl_keys(j))))) then
                            call input_error(error, src, path//"."//trim(body_stl_keys(j)) &
                                //" only applies to a body given by 'file' (a closed STL " &
                                //"surface); remove it")
                            return
                        end if
                    end do
                    call get_vector(item, "min", path, src, case%dim, body%xmin, error, &
                        required=.true., unit="m")
                    if (allocated(error)) return
                    call get_vector(item, "max", path, src, case%dim, body%xmax, error, &
                        required=.true., unit="m")
                    if (allocated(error)) return
                end if
                call get_vector(item, "velocity", path, src, case%dim, body%velocity, error, &
                    unit="m/s")
                if (allocated(error)) return
            end associate
            call check_body_box(case, i, src, error)
            if (allocated(error)) return
            total = total + case%bodies(i)%particles
        end do
        if (total > huge(1)) then
            call input_error(error, src, "the bodies hold "//int_text(total)//" particles, more " &
                //"than the "//int_text(huge(1))//" this version can store; use a smaller " &
                //"particles.ppc or a larger domain.dx")
        end if
    end subroutine read_bodies

    !> An STL body (`file`, `scale`, `offset`): reads the surface, refuses an open one or one
    !> given together with `min`/`max`, and sets min/max to its bounding box.
    subroutine read_body_surface(item, path, src, case, body, error)
        type(json_value_type), intent(in) :: item
            !! the body's object
        character(len=*), intent(in) :: path
            !! key path of the body ("bodies[i]")
        character(len=*), intent(in) :: src
            !! case file name for messages
        type(case_type), intent(in) :: case
            !! case being resolved (dimension set)
        type(body_spec_type), intent(inout) :: body
            !! the body (name set)
        type(error_type), allocatable, intent(out) :: error
            !! first error found

        type(stl_mesh_type) :: mesh
        type(error_type), allocatable :: stl_error
        character(len=:), allocatable :: label, message
        logical :: exists, closed

        label = path//' "'//body%name//'"'
        if (json_is_valid(json_get(item, "min")) .or. json_is_valid(json_get(item, "max"))) &
            then
            call input_error(error, src, label//": give either 'file' (a closed STL surface) " &
                //"or 'min' and 'max' (a box), not both")
            return
        end if
        body%file = ""
        call get_path(item, "file", path, src, 0, body%file, error, required=.true.)
        if (allocated(error)) return
        inquire (file=body%file, exist=exists)
        if (len(body%file) == 0 .or. .not. exists) then
            call input_error(error, src, path//".file: STL file '"//body%file//"' not found " &
                //"(a relative path is taken from the current working directory)")
            return
        end if
        call get_real(item, "scale", path, src, body%scale, error, above=0.0_wp)
        if (allocated(error)) return
        call get_vector(item, "offset", path, src, 3, body%offset, error, unit="m")
        if (allocated(error)) return
        call read_stl(body%file, mesh, stl_error, body%scale, body%offset, path//".file")
        if (allocated(stl_error)) then
            call fatal_error(error, src//": "//stl_error%message, stl_error%code)
            return
        end if
        call check_closed(mesh, closed, message, stl_error)
        if (allocated(stl_error)) then
            call fatal_error(error, src//": "//stl_error%message, stl_error%code)
            return
        end if
        if (.not. closed) then
            call input_error(error, src, label//": the surface '"//body%file//"' is not closed: " &
                //message//"; a body needs a closed surface")
            return
        end if
        body%xmin = mesh%lo
        body%xmax = mesh%hi
        call move_alloc(mesh%vertex, body%triangle)
        if (case%dim == 2 .and. .not. (body%xmin(3) < 0.0_wp .and. 0.0_wp < body%xmax(3))) then
            call input_error(error, src, label//": the surface '"//body%file//"' spans z = " &
                //fmt_real(body%xmin(3))//" .. "//fmt_real(body%xmax(3))//" [m]; a 2D body " &
                //"is its section by the plane z = 0, which must cross the surface")
        end if
    end subroutine read_body_surface

    !> Geometric checks of body `i`: a proper box, inside the domain, holding particles and
    !> overlapping none of the bodies before it.
    subroutine check_body_box(case, i, src, error)
        type(case_type), intent(inout) :: case
            !! case with bodies 1..i read; body i gets its particle count
        integer, intent(in) :: i
            !! body to check
        character(len=*), intent(in) :: src
            !! case file name for messages
        type(error_type), allocatable, intent(out) :: error
            !! first error found

        character(len=:), allocatable :: label, corner, what
        real(wp) :: lower(3), upper(3), tol
        integer :: d, j, dim
        integer(i8) :: count

        dim = case%dim
        tol = box_tolerance*case%dx
        associate (body => case%bodies(i))
            label = "bodies["//int_text(i)//'] "'//body%name//'"'
            corner = "corner"
            what = "the box "//fmt_box(body%xmin(1:dim), body%xmax(1:dim))//" [m]"
            if (allocated(body%triangle)) then
                corner = "the bounding box of the surface '"//body%file//"', corner"
                what = "the closed surface '"//body%file//"' (bounding box " &
                    //fmt_box(body%xmin(1:dim), body%xmax(1:dim))//" [m]"
                if (dim == 2) what = what//", section by z = 0"
                what = what//")"
            end if
            do d = 1, dim
                if (.not. body%xmin(d) < body%xmax(d)) then
                    call input_error(error, src, label//": min["//int_text(d)//"] = " &
                        //fmt_real(body%xmin(d))//" must be below max["//int_text(d)//"] = " &
                        //fmt_real(body%xmax(d))//" [m]")
                    return
                end if
            end do
            lower(1:dim) = case%origin(1:dim)
            upper(1:dim) = case%origin(1:dim) + case%ncells(1:dim)*case%dx
            if (any(body%xmin(1:dim) < lower(1:dim) - tol)) then
                call input_error(error, src, label//": "//corner//" min = " &
                    //fmt_vector(body%xmin(1:dim))//" lies outside the domain " &
                    //fmt_box(lower(1:dim), upper(1:dim), domain_digits)//" [m]")
                return
            end if
            if (any(body%xmax(1:dim) > upper(1:dim) + tol)) then
                call input_error(error, src, label//": "//corner//" max = " &
                    //fmt_vector(body%xmax(1:dim))//" lies outside the domain " &
                    //fmt_box(lower(1:dim), upper(1:dim), domain_digits)//" [m]")
                return
            end if
            count = body_particle_count(case, i)
            if (count < 0) then
                call fatal_error(error, src//": "//label//": cannot allocate the memory to " &
                    //"fill the closed surface '"//body%file//"' with particles", exit_other)
                return
            end if
            case%bodies(i)%particles = count
            if (count == 0) then
                call input_error(error, src, label//": "//what//" holds no particle (with ppc = " &
                    //int_text(case%ppc)//" particles sit at origin + (i + (k - 0.5)/ppc) dx, " &
                    //"k = 1..ppc, in each cell i); make the body larger or raise particles.ppc")
                return
            end if
            do j = 1, i - 1
                associate (other => case%bodies(j))
                    if (all(min(body%xmax(1:dim), other%xmax(1:dim)) &
                        - max(body%xmin(1:dim), other%xmin(1:dim)) > tol)) then
                        call input_error(error, src, label//" overlaps bodies["//int_text(j) &
                            //'] "'//other%name//'": the boxes (bounding boxes of STL ' &
                            //"surfaces) " &
                            //fmt_box(body%xmin(1:dim), body%xmax(1:dim))//" and " &
                            //fmt_box(other%xmin(1:dim), other%xmax(1:dim))//" [m] share a " &
                            //"volume; bodies must not overlap")
                        return
                    end if
                end associate
            end do
        end associate
    end subroutine check_body_box

    !> `solver`: update scheme and shape function.
    subroutine read_solver(root, src, case, error)
        type(json_value_type), intent(in) :: root
            !! top-level object
        character(len=*), intent(in) :: src
            !! case file name for messages
        type(case_type), intent(inout) :: case
            !! case being resolved
        type(error_type), allocatable, intent(out) :: error
            !! first error found

        type(json_value_type) :: solver
        logical :: found
        integer :: choice

        call get_section(root, "solver", "", src, solver_keys, solver, error, found=found)
        if (allocated(error) .or. .not. found) return
        call get_choice(solver, "scheme", "solver", src, scheme_names, &
            [scheme_usf, scheme_usl, scheme_musl], case%scheme, error)
        if (allocated(error)) return
        call get_choice(solver, "shape_function", "solver", src, &
            [character(len=6) :: shape_names, "gimp"], [shape_linear, shape_cpgimp, shape_cpgimp], &
            case%shape, error)
        if (allocated(error)) return
        choice = merge(1, 0, case%fbar)
        call get_choice(solver, "locking_correction", "solver", src, &
            [character(len=4) :: "none", "fbar"], [0, 1], choice, error)
        case%fbar = choice == 1
        if (allocated(error)) return
        choice = merge(1, 0, case%apic)
        call get_choice(solver, "transfer", "solver", src, [character(len=4) :: "flip", "apic"], &
            [0, 1], choice, error)
        if (allocated(error)) return
        case%apic = choice == 1
        call get_real(solver, "flip_fraction", "solver", src, case%flip_fraction, error, &
            at_least=0.0_wp, at_most=1.0_wp, unit="-", found=found)
        if (allocated(error)) return
        if (found .and. case%apic) then
            call input_error(error, src, "solver.flip_fraction applies to solver.transfer = " &
                //'"flip" only (here "apic", whose velocity update has no FLIP part); remove it')
        end if
    end subroutine read_solver

    !> `time`: end time and either a fixed step or a CFL factor.
    subroutine read_time(root, src, case, error)
        type(json_value_type), intent(in) :: root
            !! top-level object
        character(len=*), intent(in) :: src
            !! case file name for messages
        type(case_type), intent(inout) :: case
            !! case being resolved (materials and bodies set)
        type(error_type), allocatable, intent(out) :: error
            !! first error found

        type(json_value_type) :: time
        character(len=:), allocatable :: rule
        logical :: viscous
        real(wp) :: critical, step

        call get_section(root, "time", "", src, time_keys, time, error, required=.true.)
        if (allocated(error)) return
        call get_real(time, "tend", "time", src, case%tend, error, required=.true., &
            above=0.0_wp, unit="s")
        if (allocated(error)) return
        call get_bool(time, "allow_unstable", "time", src, case%allow_unstable, error)
        if (allocated(error)) return
        call case_critical_step(case, critical, viscous)
        rule = "dx / max(c_p + |v|)"
        if (viscous) rule = "the viscous limit rho dx^2 / (2 dim viscosity) of a newtonian " &
            //"material"
        if (json_is_valid(json_get(time, "dt"))) then
            if (json_is_valid(json_get(time, "cfl"))) then
                call input_error(error, src, "time.dt and time.cfl are alternatives, give only " &
                    //"one: dt for a fixed time step [s], cfl for a step set by the CFL " &
                    //"condition")
                return
            end if
            call get_real(time, "dt", "time", src, case%dt, error, above=0.0_wp, unit="s")
            if (allocated(error)) return
            if (case%dt > critical .and. .not. case%allow_unstable) then
                call input_error(error, src, "time.dt = "//fmt_real(case%dt)//" s is above the " &
                    //"critical time step "//fmt_below(critical, case%dt)//" s of this case " &
                    //"("//rule//"); use a smaller dt or set time.cfl instead "// &
                    "(time.allow_unstable = true forces it, for stability tests)")
                return
            end if
            step = case%dt
        else
            if (case%allow_unstable) then
                call get_real(time, "cfl", "time", src, case%cfl, error, above=0.0_wp)
            else
                call get_real(time, "cfl", "time", src, case%cfl, error, above=0.0_wp, &
                    at_most=1.0_wp)
            end if
            if (allocated(error)) return
            step = case%cfl*critical
        end if
        if (case%tend/max_steps > step) then
            call input_error(error, src, "time.tend = "//fmt_real(case%tend)//" s needs more " &
                //"than "//fmt_real(max_steps)//" steps of "//fmt_real(step, 6)//" s; " &
                //"shorten time.tend or allow a larger time step")
        end if
    end subroutine read_time

    !> `damping`: type, and the coefficient of local damping.
    subroutine read_damping(root, src, case, error)
        type(json_value_type), intent(in) :: root
            !! top-level object
        character(len=*), intent(in) :: src
            !! case file name for messages
        type(case_type), intent(inout) :: case
            !! case being resolved
        type(error_type), allocatable, intent(out) :: error
            !! first error found

        type(json_value_type) :: damping
        logical :: found

        call get_section(root, "damping", "", src, damping_keys, damping, error, found=found)
        if (allocated(error) .or. .not. found) return
        call get_choice(damping, "type", "damping", src, damping_names, &
            [damping_none, damping_local, damping_kinetic], case%damping, error)
        if (allocated(error)) return
        if (case%damping == damping_local) then
            call get_real(damping, "value", "damping", src, case%damping_value, error, &
                required=.true., at_least=0.0_wp, below=1.0_wp)
        else if (json_is_valid(json_get(damping, "value"))) then
            call input_error(error, src, 'damping.value only applies to damping.type = "local"' &
                //' (here "'//trim(damping_names(case%damping))//'"); remove it')
        end if
    end subroutine read_damping

    !> `contact`: "none", or "terrain_stl": frictional contact with the rigid surface of an
    !> STL file (mu, file; optional scale and offset of its coordinates).
    subroutine read_contact(root, src, case, error)
        type(json_value_type), intent(in) :: root
            !! top-level object
        character(len=*), intent(in) :: src
            !! case file name for messages
        type(case_type), intent(inout) :: case
            !! case being filled
        type(error_type), allocatable, intent(out) :: error
            !! first error found

        type(json_value_type) :: contact
        logical :: found, exists
        integer :: k, code

        call get_typed(root, "contact", "", src, "object", "an object", contact, found, error)
        if (allocated(error) .or. .not. found) return
        call check_keys(contact, "contact", contact_keys, src, error)
        if (allocated(error)) return
        code = 0
        call get_choice(contact, "type", "contact", src, &
            [character(len=11) :: "none", "terrain_stl"], [0, 1], code, error)
        if (allocated(error)) return
        if (code == 0) then
            do k = 2, size(contact_keys)
                if (json_is_valid(json_get(contact, trim(contact_keys(k))))) then
                    call input_error(error, src, "contact."//trim(contact_keys(k))// &
                        ' only applies to contact.type = "terrain_stl"; remove it')
                    return
                end if
            end do
            return
        end if
        case%contact_type = "terrain_stl"
        call get_real(contact, "mu", "contact", src, case%contact_mu, error, required=.true., &
            at_least=0.0_wp)
        if (allocated(error)) return
        call get_path(contact, "file", "contact", src, 0, case%contact_file, error, &
            required=.true.)
        if (allocated(error)) return
        inquire (file=case%contact_file, exist=exists)
        if (len(case%contact_file) == 0 .or. .not. exists) then
            call input_error(error, src, "contact.file: STL file '"//case%contact_file// &
                "' not found (a relative path is taken from the current working directory)")
            return
        end if
        call get_real(contact, "scale", "contact", src, case%contact_scale, error, &
            above=0.0_wp)
        if (allocated(error)) return
        call get_vector(contact, "offset", "contact", src, 3, case%contact_offset, error, &
            unit="m")
    end subroutine read_contact

    !> `output`: folder, intervals and fields.
    subroutine read_output(root, src, case, error)
        type(json_value_type), intent(in) :: root
            !! top-level object
        character(len=*), intent(in) :: src
            !! case file name for messages
        type(case_type), intent(inout) :: case
            !! case being resolved (name and tend set)
        type(error_type), allocatable, intent(out) :: error
            !! first error found

        type(json_value_type) :: output
        logical :: found

        case%output_interval = case%tend/20.0_wp
        case%output_dir = "outputs/"//case%name
        case%history_interval = case%output_interval/10.0_wp
        call get_section(root, "output", "", src, output_keys, output, error, found=found)
        if (allocated(error) .or. .not. found) return
        call get_real(output, "interval", "output", src, case%output_interval, error, &
            at_least=0.0_wp, unit="s")
        if (allocated(error)) return
        case%history_interval = case%output_interval/10.0_wp
        call read_fields(output, src, case%output_fields, error)
        if (allocated(error)) return
        call get_bool(output, "grid", "output", src, case%output_grid, error)
        if (allocated(error)) return
        call get_path(output, "directory", "output", src, room_folder, case%output_dir, error)
        if (allocated(error)) return
        call get_bool(output, "overwrite", "output", src, case%overwrite, error)
        if (allocated(error)) return
        call get_real(output, "history_interval", "output", src, case%history_interval, error, &
            at_least=0.0_wp, unit="s")
    end subroutine read_output

    !> `output.fields`: unique field names; the position is always written.
    subroutine read_fields(output, src, fields, error)
        type(json_value_type), intent(in) :: output
            !! the output object
        character(len=*), intent(in) :: src
            !! case file name for messages
        logical, intent(inout) :: fields(nfields)
            !! which fields are written
        type(error_type), allocatable, intent(out) :: error
            !! first error found

        character(len=*), parameter :: expect = "an array of field names"
        type(json_value_type) :: list, item
        character(len=:), allocatable :: path
        logical :: found
        integer :: i, f

        call get_typed(output, "fields", "output", src, "array", expect, list, found, error)
        if (allocated(error) .or. .not. found) return
        fields = .false.
        do i = 1, json_size(list)
            path = "output.fields["//int_text(i)//"]"
            item = json_item(list, i)
            call check_type(item, path, "string", "a field name", src, error)
            if (allocated(error)) return
            do f = 1, nfields
                if (same(lower(json_string(item)), trim(field_names(f)))) exit
            end do
            if (f > nfields) then
                call input_error(error, src, path//' = "'//json_string(item)//'" is not a ' &
                    //"field: must be one of "//quoted_list(field_names))
                return
            end if
            if (fields(f)) then
                call input_error(error, src, path//' = "'//json_string(item)//'" is listed ' &
                    //"twice; give each field once")
                return
            end if
            fields(f) = .true.
        end do
        fields(field_position) = .true.
    end subroutine read_fields

    !> `progress`: wall-clock seconds between progress lines.
    subroutine read_progress(root, src, case, error)
        type(json_value_type), intent(in) :: root
            !! top-level object
        character(len=*), intent(in) :: src
            !! case file name for messages
        type(case_type), intent(inout) :: case
            !! case being resolved
        type(error_type), allocatable, intent(out) :: error
            !! first error found

        type(json_value_type) :: progress
        logical :: found

        call get_section(root, "progress", "", src, progress_keys, progress, error, found=found)
        if (allocated(error) .or. .not. found) return
        call get_real(progress, "interval", "progress", src, case%progress_seconds, error, &
            above=0.0_wp, unit="s")
    end subroutine read_progress

    !> `checkpoint`: when to write the state of the run for a restart, and where.
    subroutine read_checkpoint(root, src, case, error)
        type(json_value_type), intent(in) :: root
            !! top-level object
        character(len=*), intent(in) :: src
            !! case file name for messages
        type(case_type), intent(inout) :: case
            !! case being resolved
        type(error_type), allocatable, intent(out) :: error
            !! first error found

        type(json_value_type) :: checkpoint
        logical :: found

        call get_section(root, "checkpoint", "", src, checkpoint_keys, checkpoint, error, &
            found=found)
        if (allocated(error) .or. .not. found) return
        call get_int(checkpoint, "every_steps", "checkpoint", src, case%checkpoint_steps, &
            error, at_least=1)
        if (allocated(error)) return
        call get_real(checkpoint, "every_minutes", "checkpoint", src, case%checkpoint_minutes, &
            error, above=0.0_wp, unit="min")
        if (allocated(error)) return
        call get_path(checkpoint, "file", "checkpoint", src, room_written, &
            case%checkpoint_file, error)
        if (allocated(error)) return
        call get_bool(checkpoint, "on_signal", "checkpoint", src, case%checkpoint_on_signal, &
            error)
    end subroutine read_checkpoint

    !> `guard`: the blow-up guard's energy bound and its copies of the healthy state.
    subroutine read_guard(root, src, case, error)
        type(json_value_type), intent(in) :: root
            !! top-level object
        character(len=*), intent(in) :: src
            !! case file name for messages
        type(case_type), intent(inout) :: case
            !! case being resolved
        type(error_type), allocatable, intent(out) :: error
            !! first error found

        type(json_value_type) :: guard
        logical :: found

        call get_section(root, "guard", "", src, guard_keys, guard, error, found=found)
        if (allocated(error) .or. .not. found) return
        call get_real(guard, "energy_factor", "guard", src, case%guard_energy_factor, error, &
            above=0.0_wp)
        if (allocated(error)) return
        call get_int(guard, "snapshot_steps", "guard", src, case%guard_snapshot_steps, error, &
            at_least=0)
    end subroutine read_guard

    ! ----------------------------------------------------------------------------------------
    ! Typed getters: each reads one key, checks it and writes the message when it is wrong
    ! ----------------------------------------------------------------------------------------

    !> Look `key` up in `obj` and check its JSON type. A missing key is an error only when
    !> `required`; otherwise `found` is false and nothing else happens.
    subroutine get_typed(obj, key, path, src, kind, expect, val, found, error, required)
        type(json_value_type), intent(in) :: obj
            !! object holding the key
        character(len=*), intent(in) :: key
            !! key to read
        character(len=*), intent(in) :: path
            !! path of `obj` ("" at the top level)
        character(len=*), intent(in) :: src
            !! case file name for messages
        character(len=*), intent(in) :: kind
            !! expected JSON type, as json_type_name spells it
        character(len=*), intent(in) :: expect
            !! what is allowed, for messages ("a number > 0 [m]")
        type(json_value_type), intent(out) :: val
            !! the value found
        logical, intent(out) :: found
            !! whether the key is present
        type(error_type), allocatable, intent(out) :: error
            !! set for a missing required key or a wrong type
        logical, intent(in), optional :: required
            !! the key must be present (default: optional)

        val = json_get(obj, key)
        found = json_is_valid(val)
        if (found) then
            call check_type(val, join(path, key), kind, expect, src, error)
        else if (is_true(required)) then
            call input_error(error, src, "missing required key '"//join(path, key)//"' (" &
                //expect//")")
        end if
    end subroutine get_typed

    !> Check the JSON type of a value.
    subroutine check_type(val, path, kind, expect, src, error)
        type(json_value_type), intent(in) :: val
            !! value to check
        character(len=*), intent(in) :: path
            !! full key path of the value
        character(len=*), intent(in) :: kind
            !! expected JSON type, as json_type_name spells it
        character(len=*), intent(in) :: expect
            !! what is allowed, for messages
        character(len=*), intent(in) :: src
            !! case file name for messages
        type(error_type), allocatable, intent(out) :: error
            !! set when the type differs

        if (json_type_name(val) /= kind) then
            call input_error(error, src, path//" has the wrong type: expected "//expect &
                //", found "//describe(val))
        end if
    end subroutine check_type

    !> Check that a value is an object with only allowed keys, each once.
    subroutine check_object(val, path, allowed, src, error)
        type(json_value_type), intent(in) :: val
            !! value to check
        character(len=*), intent(in) :: path
            !! full key path of the value
        character(len=*), intent(in) :: allowed(:)
            !! keys the object may hold
        character(len=*), intent(in) :: src
            !! case file name for messages
        type(error_type), allocatable, intent(out) :: error
            !! set on a wrong type, an unknown key or a duplicate key

        call check_type(val, path, "object", "an object", src, error)
        if (allocated(error)) return
        call check_keys(val, path, allowed, src, error)
    end subroutine check_object

    !> Refuse unknown keys (suggesting the nearest allowed key) and duplicate keys.
    !>
    !> With `owner` (objects whose keys depend on a type, like a material) the message also
    !> lists the keys of that owner, and a key of `known` (valid for another type) is named
    !> as such rather than matched to a look-alike.
    subroutine check_keys(obj, path, allowed, src, error, owner, known)
        type(json_value_type), intent(in) :: obj
            !! object to check
        character(len=*), intent(in) :: path
            !! full key path of the object ("" at the top level)
        character(len=*), intent(in) :: allowed(:)
            !! keys the object may hold
        character(len=*), intent(in) :: src
            !! case file name for messages
        type(error_type), allocatable, intent(out) :: error
            !! set on the first unknown or duplicate key
        character(len=*), intent(in), optional :: owner
            !! what the object is, for messages ("a newtonian material")
        character(len=*), intent(in), optional :: known(:)
            !! keys valid for other types of the same object (only with `owner`)

        character(len=:), allocatable :: key, where, message, keys_text
        integer :: i, j, k, best, dist, best_dist

        where = "the top level"
        if (len(path) > 0) where = path
        keys_text = "; the keys allowed in "//where//" are: "//plain_list(allowed)
        if (present(owner)) keys_text = "; the keys of "//owner//" are: "//plain_list(allowed)
        do i = 1, json_size(obj)
            key = json_key(json_item(obj, i))
            best = 0
            best_dist = huge(1)
            do k = 1, size(allowed)
                dist = levenshtein(lower(key), lower(trim(allowed(k))))
                if (same(key, trim(allowed(k)))) dist = -1
                ! a suggestion sharing no letter with the key would only mislead
                if (dist > 0 .and. dist >= max(len(key), len_trim(allowed(k)))) dist = huge(1)
                if (dist < best_dist) then
                    best = k
                    best_dist = dist
                end if
            end do
            if (best_dist >= 0) then
                message = "unknown key '"//join(path, key)//"'"
                if (present(owner) .and. present(known)) then
                    if (any_same(known, key)) then
                        call input_error(error, src, message//": "//key//" is not a " &
                            //"parameter of "//owner//keys_text)
                        return
                    end if
                end if
                if (best_dist == 0) then
                    message = message//"; did you mean '"//trim(allowed(best))//"'? (keys " &
                        //"are case-sensitive)"
                else if (best_dist <= 3) then
                    message = message//"; did you mean '"//trim(allowed(best))//"'?"
                else
                    message = message//keys_text
                end if
                if (present(owner) .and. best_dist <= 3) then
                    message = message//" The keys of "//owner//" are: "//plain_list(allowed)
                end if
                call input_error(error, src, message)
                return
            end if
            do j = 1, i - 1
                if (same(json_key(json_item(obj, j)), key)) then
                    call input_error(error, src, "duplicate key '"//join(path, key)//"': it " &
                        //"appears more than once in "//where//"; give each key once")
                    return
                end if
            end do
        end do
    end subroutine check_keys

    !> Read an optional or required object and check its keys.
    subroutine get_section(obj, key, path, src, allowed, sec, error, required, found)
        type(json_value_type), intent(in) :: obj
            !! object holding the section
        character(len=*), intent(in) :: key
            !! section key
        character(len=*), intent(in) :: path
            !! path of `obj` ("" at the top level)
        character(len=*), intent(in) :: src
            !! case file name for messages
        character(len=*), intent(in) :: allowed(:)
            !! keys the section may hold
        type(json_value_type), intent(out) :: sec
            !! the section (invalid when absent)
        type(error_type), allocatable, intent(out) :: error
            !! first error found
        logical, intent(in), optional :: required
            !! the section must be present
        logical, intent(out), optional :: found
            !! whether the section is present

        logical :: is_present

        call get_typed(obj, key, path, src, "object", "an object", sec, is_present, error, &
            required)
        if (present(found)) found = is_present
        if (allocated(error) .or. .not. is_present) return
        call check_keys(sec, join(path, key), allowed, src, error)
    end subroutine get_section

    !> Read a required, non-empty top-level array (`materials`, `bodies`).
    subroutine get_list(root, key, src, what, list, error)
        type(json_value_type), intent(in) :: root
            !! top-level object
        character(len=*), intent(in) :: key
            !! array key
        character(len=*), intent(in) :: src
            !! case file name for messages
        character(len=*), intent(in) :: what
            !! what one item is, for messages ("material")
        type(json_value_type), intent(out) :: list
            !! the array
        type(error_type), allocatable, intent(out) :: error
            !! first error found

        logical :: found

        call get_typed(root, key, "", src, "array", "a non-empty array of "//what//" objects", &
            list, found, error, required=.true.)
        if (allocated(error)) return
        if (json_size(list) == 0) then
            call input_error(error, src, key//" is an empty array: give at least one "//what)
        end if
    end subroutine get_list

    !> Read a real number, optionally bounded. The value is left as it is when the key is absent.
    subroutine get_real(obj, key, path, src, value, error, required, above, at_least, below, &
            at_most, unit, found)
        type(json_value_type), intent(in) :: obj
            !! object holding the key
        character(len=*), intent(in) :: key
            !! key to read
        character(len=*), intent(in) :: path
            !! path of `obj`
        character(len=*), intent(in) :: src
            !! case file name for messages
        real(wp), intent(inout) :: value
            !! value read (unchanged when absent)
        type(error_type), allocatable, intent(out) :: error
            !! first error found
        logical, intent(in), optional :: required
            !! the key must be present
        real(wp), intent(in), optional :: above
            !! value must be > above
        real(wp), intent(in), optional :: at_least
            !! value must be >= at_least
        real(wp), intent(in), optional :: below
            !! value must be < below
        real(wp), intent(in), optional :: at_most
            !! value must be <= at_most
        character(len=*), intent(in), optional :: unit
            !! unit shown in messages
        logical, intent(out), optional :: found
            !! whether the key is present

        type(json_value_type) :: val
        character(len=:), allocatable :: allowed
        logical :: is_present
        real(wp) :: x

        allowed = range_text(above, at_least, below, at_most, unit)
        call get_typed(obj, key, path, src, "number", "a number"//allowed, val, is_present, &
            error, required)
        if (present(found)) found = is_present
        if (allocated(error) .or. .not. is_present) return
        call number_value(val, join(path, key), src, x, error)
        if (allocated(error)) return
        if (.not. in_range(x, above, at_least, below, at_most)) then
            call input_error(error, src, join(path, key)//" = "//fmt_real(x) &
                //" is out of range: must be"//allowed)
            return
        end if
        value = x
    end subroutine get_real

    !> Read a whole number (2.0 is fine, 2.5 is not) in [at_least, at_most].
    subroutine get_int(obj, key, path, src, value, error, required, at_least, at_most)
        type(json_value_type), intent(in) :: obj
            !! object holding the key
        character(len=*), intent(in) :: key
            !! key to read
        character(len=*), intent(in) :: path
            !! path of `obj`
        character(len=*), intent(in) :: src
            !! case file name for messages
        integer, intent(inout) :: value
            !! value read (unchanged when absent)
        type(error_type), allocatable, intent(out) :: error
            !! first error found
        logical, intent(in), optional :: required
            !! the key must be present
        integer, intent(in), optional :: at_least
            !! smallest allowed value (default -huge(1))
        integer, intent(in), optional :: at_most
            !! largest allowed value (default huge(1))

        type(json_value_type) :: val
        character(len=:), allocatable :: allowed
        logical :: is_present
        real(wp) :: x, lower_bound, upper_bound

        lower_bound = -real(huge(1), wp)
        upper_bound = real(huge(1), wp)
        allowed = " an integer"
        if (present(at_least)) then
            lower_bound = real(at_least, wp)
            allowed = allowed//" >= "//int_text(at_least)
        end if
        if (present(at_most)) then
            upper_bound = real(at_most, wp)
            if (present(at_least)) allowed = allowed//" and"
            allowed = allowed//" <= "//int_text(at_most)
        end if
        call get_typed(obj, key, path, src, "number", allowed(2:), val, is_present, error, &
            required)
        if (allocated(error) .or. .not. is_present) return
        call number_value(val, join(path, key), src, x, error)
        if (allocated(error)) return
        if (x /= aint(x)) then
            call input_error(error, src, join(path, key)//" = "//fmt_real(x)//" is not a " &
                //"whole number: must be"//allowed)
            return
        end if
        if (x < lower_bound .or. x > upper_bound) then
            call input_error(error, src, join(path, key)//" = "//fmt_real(x) &
                //" is out of range: must be"//allowed)
            return
        end if
        value = int(x)
    end subroutine get_int

    !> Read an array of exactly `n` numbers (one per axis).
    subroutine get_vector(obj, key, path, src, n, values, error, required, unit)
        type(json_value_type), intent(in) :: obj
            !! object holding the key
        character(len=*), intent(in) :: key
            !! key to read
        character(len=*), intent(in) :: path
            !! path of `obj`
        character(len=*), intent(in) :: src
            !! case file name for messages
        integer, intent(in) :: n
            !! number of components (the dimension)
        real(wp), intent(inout) :: values(:)
            !! components 1..n are set when the key is present
        type(error_type), allocatable, intent(out) :: error
            !! first error found
        logical, intent(in), optional :: required
            !! the key must be present
        character(len=*), intent(in), optional :: unit
            !! unit shown in messages

        type(json_value_type) :: val
        character(len=:), allocatable :: expect
        logical :: is_present
        integer :: i
        real(wp) :: x(3)

        expect = "an array of "//int_text(n)//" numbers"//range_text(unit=unit)
        call get_typed(obj, key, path, src, "array", expect, val, is_present, error, required)
        if (allocated(error) .or. .not. is_present) return
        if (json_size(val) /= n) then
            call input_error(error, src, join(path, key)//" must have "//int_text(n)//" numbers " &
                //"(one per axis, dimension = "//int_text(n)//"), found "//int_text(json_size(val)))
            return
        end if
        do i = 1, n
            associate (item_path => join(path, key)//"["//int_text(i)//"]")
                call check_type(json_item(val, i), item_path, "number", "a number", src, error)
                if (allocated(error)) return
                call number_value(json_item(val, i), item_path, src, x(i), error)
                if (allocated(error)) return
            end associate
        end do
        values(1:n) = x(1:n)
    end subroutine get_vector

    !> Read a non-empty string.
    subroutine get_string(obj, key, path, src, value, error, required, found)
        type(json_value_type), intent(in) :: obj
            !! object holding the key
        character(len=*), intent(in) :: key
            !! key to read
        character(len=*), intent(in) :: path
            !! path of `obj`
        character(len=*), intent(in) :: src
            !! case file name for messages
        character(len=:), allocatable, intent(inout) :: value
            !! value read (unchanged when absent)
        type(error_type), allocatable, intent(out) :: error
            !! first error found
        logical, intent(in), optional :: required
            !! the key must be present
        logical, intent(out), optional :: found
            !! whether the key is present

        type(json_value_type) :: val
        logical :: is_present

        call get_typed(obj, key, path, src, "string", "a non-empty string", val, is_present, &
            error, required)
        if (present(found)) found = is_present
        if (allocated(error) .or. .not. is_present) return
        if (len(json_string(val)) == 0) then
            call input_error(error, src, join(path, key)//' = "" is not allowed: must be a ' &
                //"non-empty string")
            return
        end if
        value = json_string(val)
    end subroutine get_string

    !> Read a file or folder name: a non-empty string that the system takes as a path, with
    !> `room` bytes added by the program (path_problem).
    subroutine get_path(obj, key, path, src, room, value, error, required, found)
        type(json_value_type), intent(in) :: obj
            !! object holding the key
        character(len=*), intent(in) :: key
            !! key to read
        character(len=*), intent(in) :: path
            !! path of `obj`
        character(len=*), intent(in) :: src
            !! case file name for messages
        integer, intent(in) :: room
            !! bytes the program adds: room_written, room_folder or 0 (a file it reads)
        character(len=:), allocatable, intent(inout) :: value
            !! value read (unchanged when absent)
        type(error_type), allocatable, intent(out) :: error
            !! first error found
        logical, intent(in), optional :: required
            !! the key must be present
        logical, intent(out), optional :: found
            !! whether the key is present

        character(len=:), allocatable :: problem
        logical :: is_present

        call get_string(obj, key, path, src, value, error, required, is_present)
        if (present(found)) found = is_present
        if (allocated(error) .or. .not. is_present) return
        if (room == room_folder) then
            problem = path_problem(value, room, 0)
        else
            problem = path_problem(value, room, room)
        end if
        if (len(problem) > 0) call input_error(error, src, join(path, key)//" is not a "// &
            "usable path: "//problem)
    end subroutine get_path

    !> Read a boolean.
    subroutine get_bool(obj, key, path, src, value, error)
        type(json_value_type), intent(in) :: obj
            !! object holding the key
        character(len=*), intent(in) :: key
            !! key to read
        character(len=*), intent(in) :: path
            !! path of `obj`
        character(len=*), intent(in) :: src
            !! case file name for messages
        logical, intent(inout) :: value
            !! value read (unchanged when absent)
        type(error_type), allocatable, intent(out) :: error
            !! first error found

        type(json_value_type) :: val
        logical :: is_present

        call get_typed(obj, key, path, src, "boolean", "true or false", val, is_present, error)
        if (allocated(error) .or. .not. is_present) return
        value = json_bool(val)
    end subroutine get_bool

    !> Read one of a list of names (any letter case) and return its code.
    subroutine get_choice(obj, key, path, src, names, codes, value, error, required)
        type(json_value_type), intent(in) :: obj
            !! object holding the key
        character(len=*), intent(in) :: key
            !! key to read
        character(len=*), intent(in) :: path
            !! path of `obj`
        character(len=*), intent(in) :: src
            !! case file name for messages
        character(len=*), intent(in) :: names(:)
            !! accepted names (aliases included)
        integer, intent(in) :: codes(:)
            !! code of each name
        integer, intent(inout) :: value
            !! code of the name read (unchanged when absent)
        type(error_type), allocatable, intent(out) :: error
            !! first error found
        logical, intent(in), optional :: required
            !! the key must be present

        type(json_value_type) :: val
        character(len=:), allocatable :: name
        logical :: is_present
        integer :: i

        call get_typed(obj, key, path, src, "string", "one of "//quoted_list(names), val, &
            is_present, error, required)
        if (allocated(error) .or. .not. is_present) return
        name = json_string(val)
        do i = 1, size(names)
            if (same(lower(name), lower(trim(names(i))))) then
                value = codes(i)
                return
            end if
        end do
        call input_error(error, src, join(path, key)//' = "'//name//'" is not allowed: must ' &
            //"be one of "//quoted_list(names))
    end subroutine get_choice

    !> Value of a number node, refusing numbers that overflow a double (1e999).
    subroutine number_value(val, path, src, x, error)
        type(json_value_type), intent(in) :: val
            !! a number node
        character(len=*), intent(in) :: path
            !! full key path of the value
        character(len=*), intent(in) :: src
            !! case file name for messages
        real(wp), intent(out) :: x
            !! the number
        type(error_type), allocatable, intent(out) :: error
            !! set when the number is not finite

        x = json_number(val)
        if (.not. ieee_is_finite(x)) then
            x = 0.0_wp
            call input_error(error, src, path//" is not a finite number (too large for double " &
                //"precision)")
        end if
    end subroutine number_value

    ! ----------------------------------------------------------------------------------------
    ! Case quantities
    ! ----------------------------------------------------------------------------------------

    !> Time step at t = 0 [s]: the fixed one, or cfl times the critical one (0 without
    !> materials).
    pure real(wp) function case_step(case)
        type(case_type), intent(in) :: case
            !! resolved case

        real(wp) :: critical
        logical :: viscous

        case_step = case%dt
        if (case_step > 0.0_wp) return
        case_step = 0.0_wp
        if (.not. allocated(case%materials)) return
        if (size(case%materials) == 0) return
        call case_critical_step(case, critical, viscous)
        case_step = case%cfl*critical
    end function case_step

    !> Critical time step at t = 0: over the bodies, or over the materials when the particles
    !> come from a state file (no bodies, velocities unknown here) [s]. Either way the viscous
    !> limit of the newtonian materials in use applies too.
    pure subroutine case_critical_step(case, dt, viscous)
        type(case_type), intent(in) :: case
            !! case with materials (and bodies) set
        real(wp), intent(out) :: dt
            !! critical time step [s]
        logical, intent(out) :: viscous
            !! whether the viscous limit sets the step

        real(wp) :: speed, limit
        integer :: m, b

        limit = huge(1.0_wp)
        if (allocated(case%bodies)) then
            if (size(case%bodies) > 0) then
                dt = critical_time_step(case)
                do b = 1, size(case%bodies)
                    limit = min(limit, viscous_time_step(case%materials(case%bodies(b)%material), &
                        case%dx, case%dim))
                end do
                viscous = limit < huge(1.0_wp) .and. dt >= limit
                return
            end if
        end if
        speed = 0.0_wp
        do m = 1, size(case%materials)
            speed = max(speed, p_wave_speed(case%materials(m)))
            limit = min(limit, viscous_time_step(case%materials(m), case%dx, case%dim))
        end do
        dt = limit
        if (speed > 0.0_wp) dt = min(case%dx/speed, limit)
        viscous = limit < huge(1.0_wp) .and. dt >= limit
    end subroutine case_critical_step

    !> Number of grid nodes of the case.
    pure integer(i8) function node_count(case)
        type(case_type), intent(in) :: case
            !! resolved case

        node_count = product(int(case%ncells(1:case%dim), i8) + 1_i8)
    end function node_count

    !> Number of particles of body b, from the particle generator itself (so the count and the
    !> particles always agree); -1 when the memory to fill an STL body is missing.
    integer(i8) function body_particle_count(case, b) result(count)
        type(case_type), intent(in) :: case
            !! case (grid, ppc and bodies 1..b set)
        integer, intent(in) :: b
            !! body index

        count = count_body_particles(case, b)
    end function body_particle_count

    !> Particles of body b: the reader's count, or counted now for a case made in code.
    integer(i8) function body_particles(case, b)
        type(case_type), intent(in) :: case
            !! case
        integer, intent(in) :: b
            !! body index

        body_particles = case%bodies(b)%particles
        if (body_particles < 0) body_particles = body_particle_count(case, b)
    end function body_particles

    !> Index of the material called `name`, 0 when there is none.
    pure integer function material_index(materials, name)
        type(material_spec_type), intent(in) :: materials(:)
            !! materials of the case
        character(len=*), intent(in) :: name
            !! name to find

        do material_index = 1, size(materials)
            if (same(materials(material_index)%name, name)) return
        end do
        material_index = 0
    end function material_index

    !> The material names, quoted and separated by commas.
    pure function material_list(materials) result(list)
        type(material_spec_type), intent(in) :: materials(:)
            !! materials of the case
        character(len=:), allocatable :: list

        integer :: m

        list = ""
        do m = 1, size(materials)
            if (m > 1) list = list//", "
            list = list//'"'//materials(m)%name//'"'
        end do
    end function material_list

    !> Summary lines of one material: its type and every parameter the type uses, angles in
    !> degrees.
    pure function material_text(mat) result(text)
        type(material_spec_type), intent(in) :: mat
            !! resolved material
        character(len=:), allocatable :: text

        character(len=*), parameter :: nl = new_line("a")
        character(len=:), allocatable :: head, line

        head = '  "'//text_or(mat%name, "?")//'" '//text_or(mat%type, "?")//": "
        if (mat%type == "newtonian") then
            text = head//"rho = "//fmt_real(mat%density)//" kg/m3, viscosity = " &
                //fmt_real(mat%viscosity)//" Pa s, bulk modulus = "//fmt_real(mat%bulk_modulus) &
                //" Pa, c_p = "//fmt_real(p_wave_speed(mat), 6)//" m/s"//nl
            return
        end if
        text = head//"E = "//fmt_real(mat%young)//" Pa, nu = "//fmt_real(mat%poisson) &
            //", rho = "//fmt_real(mat%density)//" kg/m3, c_p = " &
            //fmt_real(p_wave_speed(mat), 6)//" m/s"//nl
        if (mat%type /= "mohr_coulomb" .and. mat%type /= "drucker_prager") return
        line = "    phi = "//fmt_deg(mat%friction)//" deg, c = "//fmt_real(mat%cohesion) &
            //" Pa, psi = "//fmt_deg(mat%dilatancy)//" deg, tension cutoff "
        if (mat%tension_cutoff >= 0.0_wp) then
            line = line//fmt_real(mat%tension_cutoff)//" Pa"
        else
            line = line//"at the apex"
        end if
        if (mat%type == "drucker_prager") line = line//", cone "//trim(cone_names(mat%cone))
        if (mat%separation) line = line//", separation"
        text = text//line//nl
        if (mat%softening == softening_none) then
            text = text//"    no softening"//nl
        else
            text = text//"    softening "//trim(softening_names(mat%softening))//" to phi = " &
                //fmt_deg(mat%friction_residual)//" deg, c = "//fmt_real(mat%cohesion_residual) &
                //" Pa, psi = "//fmt_deg(mat%dilatancy_residual)//" deg"
            if (mat%softening == softening_linear) then
                text = text//" at plastic shear strain "//fmt_real(mat%softening_strain)//nl
            else
                text = text//", plastic shear strain scale "//fmt_real(mat%softening_strain)//nl
            end if
        end if
    end function material_text

    !> "xmin fixed", "ymin frictional (mu = 0.4)"
    pure function face_text(case, side, axis) result(text)
        type(case_type), intent(in) :: case
            !! resolved case
        integer, intent(in) :: side
            !! 1: min face, 2: max face
        integer, intent(in) :: axis
            !! axis of the face
        character(len=:), allocatable :: text

        text = axis_names(axis:axis)//trim(merge("min", "max", side == 1))//" " &
            //trim(bc_names(case%bc(side, axis)))
        if (case%bc(side, axis) == bc_frictional) then
            text = text//" (mu = "//fmt_real(case%bc_friction(side, axis))//")"
        end if
    end function face_text

    ! ----------------------------------------------------------------------------------------
    ! Text helpers
    ! ----------------------------------------------------------------------------------------

    !> Create an input error whose message starts with the case file name.
    pure subroutine input_error(error, src, message)
        type(error_type), allocatable, intent(out) :: error
            !! error to create
        character(len=*), intent(in) :: src
            !! case file name
        character(len=*), intent(in) :: message
            !! what is wrong and what is allowed

        call fatal_error(error, src//": "//message, exit_input)
    end subroutine input_error

    !> A value as messages show it: its type and, for scalars, the value.
    function describe(val) result(text)
        type(json_value_type), intent(in) :: val
            !! any value
        character(len=:), allocatable :: text

        character(len=:), allocatable :: kind, str

        kind = json_type_name(val)
        if (kind == "string") then
            str = json_string(val)
            if (len(str) > 40) str = str(1:37)//"..."
            text = 'a string ("'//str//'")'
        else if (kind == "number") then
            if (ieee_is_finite(json_number(val))) then
                text = "a number ("//fmt_real(json_number(val))//")"
            else
                text = "a number"
            end if
        else if (kind == "boolean") then
            text = "a boolean ("//trim(merge("true ", "false", json_bool(val)))//")"
        else if (kind == "array" .or. kind == "object") then
            text = "an "//kind
        else
            text = kind
        end if
    end function describe

    !> Text of the bounds of a number: " > 0 [m]", " >= 0 and < 0.5", "" for none.
    pure function range_text(above, at_least, below, at_most, unit) result(text)
        real(wp), intent(in), optional :: above
            !! strict lower bound
        real(wp), intent(in), optional :: at_least
            !! lower bound
        real(wp), intent(in), optional :: below
            !! strict upper bound
        real(wp), intent(in), optional :: at_most
            !! upper bound
        character(len=*), intent(in), optional :: unit
            !! unit of the number
        character(len=:), allocatable :: text

        text = ""
        if (present(above)) text = text//" > "//fmt_real(above)
        if (present(at_least)) text = text//" >= "//fmt_real(at_least)
        if (len(text) > 0 .and. (present(below) .or. present(at_most))) text = text//" and"
        if (present(below)) text = text//" < "//fmt_real(below)
        if (present(at_most)) text = text//" <= "//fmt_real(at_most)
        if (present(unit)) text = text//" ["//unit//"]"
    end function range_text

    !> Whether x satisfies every bound given.
    pure logical function in_range(x, above, at_least, below, at_most)
        real(wp), intent(in) :: x
            !! value to test
        real(wp), intent(in), optional :: above
            !! strict lower bound
        real(wp), intent(in), optional :: at_least
            !! lower bound
        real(wp), intent(in), optional :: below
            !! strict upper bound
        real(wp), intent(in), optional :: at_most
            !! upper bound

        in_range = .true.
        if (present(above)) in_range = in_range .and. x > above
        if (present(at_least)) in_range = in_range .and. x >= at_least
        if (present(below)) in_range = in_range .and. x < below
        if (present(at_most)) in_range = in_range .and. x <= at_most
    end function in_range

    !> An angle given in radians, as degrees: enough digits to hide the round-off of the
    !> conversion, so 30 degrees shows as "30".
    pure function fmt_deg(angle) result(text)
        real(wp), intent(in) :: angle
            !! angle [rad]
        character(len=:), allocatable :: text

        text = fmt_real(angle/degree, 12)
    end function fmt_deg

    !> A case name is safe as a folder name: letters, digits, '-', '_', '.', not leading '.'.
    pure logical function valid_name(name)
        character(len=*), intent(in) :: name
            !! case name

        character(len=*), parameter :: allowed = "abcdefghijklmnopqrstuvwxyz" &
            //"ABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789-_."

        valid_name = len(name) > 0
        if (.not. valid_name) return
        valid_name = name(1:1) /= "." .and. verify(name, allowed) == 0
    end function valid_name

    !> True when the optional flag is present and true.
    pure logical function is_true(flag)
        logical, intent(in), optional :: flag
            !! optional flag

        is_true = .false.
        if (present(flag)) is_true = flag
    end function is_true

end submodule mpm_case_reader
